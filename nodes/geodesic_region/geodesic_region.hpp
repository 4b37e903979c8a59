// The target region F^T of topology-free cut and paste (../papers/topology-free-cut-and-paste.txt,
// "geodesic walk"; spec alternatives-001-004 section 2.2): the source base's boundary polygon,
// walked on the target as straightest geodesics (Polthier-Schmies) from the target DEM's origin,
// scaled by its lambda and turned by the polygon's corner angles, closed, and filled on its inner
// side.
#pragma once

#include <Eigen/Core>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/geodesic_walk.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/surface_point.hpp"

namespace geobrush {

struct GeodesicRegionOptions {
  // How far placement.origin.point may lie from the target, relative to its bounding diagonal.
  double originTolerance = 1e-2;
  // The share of the loop's length beyond which the closing gap deserves a warning: a flat
  // polygon walked on a surface of curvature K misses closing by about its area times K times
  // its radius, 5% of the loop for a disc of radius 0.3 / sqrt(K).
  double gapWarning = 0.05;
  // Tries at aiming the last side at the first corner (each one walk of the last side).
  int aimIterations = 32;
  // Newton steps for the bend and stretch that close the loop (each three walks of the loop).
  int closingIterations = 16;
  GeodesicWalkOptions walk;
};

// An input that gives no region. `option()` names the input to change: "base", "placement" or
// "target".
class GeodesicRegionError : public std::invalid_argument {
 public:
  GeodesicRegionError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// A straight piece of the walked loop inside one face, of positive length.
struct LoopPiece {
  int face = -1;
  Eigen::Vector3d from = Eigen::Vector3d::Zero();
  Eigen::Vector3d to = Eigen::Vector3d::Zero();
};

struct WalkedLoop {
  SurfacePoint start;                   // the placement's origin on the target
  std::vector<int> cornerFace;          // per polygon corner
  std::vector<Eigen::Vector3d> corner;  // per polygon corner, where the walk reached it
  // The closed loop from the first corner round to it again, in order; the last side aimed at
  // the first corner so that it ends there.
  std::vector<LoopPiece> pieces;
  double gap = 0;  // how far the last side, walked as the polygon says, ends from corner 0
  // The shape that closes the loop: side i walked 1 + stretch . (its unit direction in the
  // domain) times its length, each corner turned by `bend` radians per unit length of the side
  // it starts beyond the polygon's angle.
  Eigen::Vector2d stretch = Eigen::Vector2d::Zero();
  double bend = 0;
  double length = 0;  // lambda times the polygon's perimeter
  int vertices = 0;   // mesh vertices the loop passed through
};

struct GeodesicRegionResult {
  Canvas region;  // F^T on the target
  WalkedLoop loop;
  std::vector<int> crossed;   // target faces the loop runs through, increasing
  std::vector<int> enclosed;  // target faces inside it, increasing
};

// Throws GeodesicRegionError. Stages below.
GeodesicRegionResult geodesicRegion(const MeshPtr& target, const Parameterization& base,
                                    const Parameterization& placement,
                                    const GeodesicRegionOptions& options = {});

// The base's boundary polygon p_0..p_{m-1}: the uv of its canvas's boundary loop, in order.
// Throws GeodesicRegionError("base") unless it is a simple polygon of at least 3 distinct corners.
std::vector<Eigen::Vector2d> basePolygon(const Parameterization& base);

// Twice the polygon's signed area (positive counter-clockwise).
double signedArea2(const std::vector<Eigen::Vector2d>& polygon);

// The tangent directions of the domain axes u and v on the start face: the frame's axes turned
// by the smallest rotation taking its normal to the face's (the frame's axes already hold the
// placement's rotation). Throws GeodesicRegionError("placement") when they face away.
std::pair<Eigen::Vector3d, Eigen::Vector3d> startAxes(const TriMesh& target, int face,
                                                      const Frame& frame);

// The spec's walk (paper, "geodesic walk"): from the start, lambda |p_0| toward p_0 to corner 0,
// then lambda |p_{i+1} - p_i| per side, turning at each corner by the polygon's corner angle
// (atan2(a x b, a . b) of consecutive sides); `gap` is how far that misses closing. Where the
// target curves, the loop is then walked with a uniform bend and stretch that close it (the
// curvature it encloses turns the heading, Gauss-Bonnet), and its last side re-aimed at corner 0.
WalkedLoop walkLoop(const TriMesh& target, const SurfacePoint& start, const Frame& frame,
                    double scale, const std::vector<Eigen::Vector2d>& polygon,
                    const GeodesicRegionOptions& options);

// The faces the loop crosses, then those enclosed on its inner side (its left when `innerLeft`):
// the faces not crossed reached from those bordering the loop on its inner side, through faces
// not crossed (which must not reach one bordering it on the outer side). Throws
// GeodesicRegionError("placement") where the loop crosses or touches itself, or would take the
// whole target.
std::pair<std::vector<int>, std::vector<int>> loopFaces(const TriMesh& target,
                                                        const WalkedLoop& loop, bool innerLeft);

}  // namespace geobrush
