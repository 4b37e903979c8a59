// The direct projective mapping (DPM) of "Mesh Geometric Editing Approach Based on GPU Texture"
// (../shared/papers/gpu-texture-cloning.txt, section 2; equations E1-E3 as labelled in
// specs/alternatives-001-004.md 1.2): vertices projected orthogonally onto the plane P through the
// centre, whose normal is the view direction. Shared by the source map (geobrush.dpm), the target
// stamp (geobrush.dpm_target) and the 3D retrieval (geobrush.dpm_lift).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// An input that gives no projective map. `option()` names what to change: "canvas", "view",
// "angle", "reversed_ring" or "crop_to_disc".
class ProjectiveMapError : public std::invalid_argument {
 public:
  ProjectiveMapError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// The frame of the plane P through `point` with normal `view` (non-zero, any length): the axes
// follow originFrame's conventions (v = the global +y projected onto P, or +z when the view is
// along y; u = v x n; both turned by `angleDegrees` about n).
Frame viewFrame(const Eigen::Vector3d& point, const Eigen::Vector3d& view, double angleDegrees);

// E1: the coordinates of x projected onto the plane, along the frame's u and v axes:
// ((x - o) . e_u, (x - o) . e_v). Exactly (0, 0) at the frame's point.
Eigen::Vector2d projectOntoPlane(const Frame& plane, const Eigen::Vector3d& x);

// The preserved vertex offset h = (x - o) . n_P: how far x stands above the plane.
double offsetFromPlane(const Frame& plane, const Eigen::Vector3d& x);

// The unit surface normal at `point` of face `face`: the angle-weighted vertex normals of its
// corners interpolated there (originFrame's rule). Zero where the face and its corners have none.
Eigen::Vector3d surfaceNormalAt(const TriMesh& mesh, int face, const Eigen::Vector3d& point);

// Faces whose normal . view <= 0 (the projection folds them or sees them edge-on; zero-area faces
// included), grown `rings` times by every face sharing a vertex with a flagged one.
std::vector<std::uint8_t> foldedFaces(const TriMesh& mesh, const Eigen::Vector3d& view, int rings);

struct ProjectiveMapOptions {
  // The view direction n_P (any length); zero: the direction of the canvas' vector area (the view
  // under which it shows its largest area), or for a canvas that nearly closes, the source
  // surface normal at the canvas origin.
  Eigen::Vector3d view = Eigen::Vector3d::Zero();
  // Turns the (u, v) axes about n_P, as DemOptions::angleDegrees does.
  double angleDegrees = 0;
  // The centre v_o of the plane: false, the canvas origin point (the shared domain's convention,
  // uv(origin) = (0, 0)); true, the canvas origin vertex (the paper's "centre vertex").
  bool centerAtVertex = false;
  // Crops the canvas to the faces whose three corners project within the largest disc around the
  // centre that the projected outline holds (the paper's round decal), flood-filled from the
  // origin face.
  bool cropToDisc = false;
  // Rings the fold flags grow by (as GeoBrush section 4.5 grows its reversed flags).
  int reversedRing = 3;
};

struct ProjectiveMapResult {
  CanvasPtr canvas;                         // the input canvas, or its crop
  std::vector<Eigen::Vector2d> uv;          // E1, per canvas surface vertex, metric units
  std::vector<double> offset;               // h, per canvas surface vertex
  Frame origin;                             // plane P: point v_o, normal n_P, the (u, v) axes
  std::vector<std::uint8_t> reversedFaces;  // per canvas face: foldedFaces, grown
};

// E1 over a canvas. Throws ProjectiveMapError for an empty or inconsistent canvas, a non-finite
// or zero view, a non-finite angle, a negative ring count, a canvas origin with no surface normal
// (default view) and a crop that leaves no single-loop region.
ProjectiveMapResult projectiveMap(const CanvasPtr& canvas, const ProjectiveMapOptions& options);

// E2 and E3: texel coordinates (s, t) = uv / (sqrt(2) R) + (0.5, 0.5), R the largest |uv|, so
// that the square [0, 1]^2 is inscribed in the decal's disc.
struct TexelCoordinates {
  double radius = 0;                // R
  std::vector<Eigen::Vector2d> st;  // per uv
};
// Throws std::invalid_argument when uv is empty, not finite or all (0, 0).
TexelCoordinates texelCoordinates(const std::vector<Eigen::Vector2d>& uv);

// The inverse of E2/E3: the domain point of texel coordinates (s, t) for the decal radius R.
Eigen::Vector2d domainOfTexel(const Eigen::Vector2d& st, double radius);

// A canvas on `faces` of `mesh` (increasing face indices, one manifold region): the submesh,
// its source maps, the boundary loop from its lowest vertex and the origin in mesh face
// `originFace` (one of `faces`). Throws std::invalid_argument where the faces are not manifold.
Canvas canvasOnFaces(const MeshPtr& mesh, const std::vector<int>& faces, int originFace,
                     const Eigen::Vector3d& originPoint);

}  // namespace geobrush
