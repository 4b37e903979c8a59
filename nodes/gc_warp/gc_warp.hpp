// 3D Green coordinates (Lipman, Levin, Cohen-Or, "Green Coordinates", SIGGRAPH 2008) of points
// inside a triangle cage, and the space deformation they define.
#pragma once

#include <Eigen/Core>
#include <functional>

#include <stdexcept>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

// A cage that cannot be used: open, non-manifold, inward oriented, with a degenerate face, or
// (for a deformed cage) with other connectivity than the cage the coordinates were computed for.
class CageError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct GreenOptions {
  // Points closer than epsilon * (cage bounding-box diagonal) to a face's plane are treated as
  // lying in that plane, and those also within that distance of the face itself as lying on the
  // cage: their coordinates are the limit from inside the cage. Unsnapped points at distance
  // delta lose about 1e-16 * size / delta to rounding near an edge, so 1e-8 keeps the
  // reproduction error near 1e-9 of the cage's size everywhere.
  double epsilon = 1e-8;
  // Worker threads; 0 uses every hardware thread. The result is bit-identical for any count.
  int threads = 0;
  // Called on the calling thread with the fraction of points done; may throw to stop.
  std::function<void(double)> progress;
};

struct GreenCoordinatesResult {
  GreenCoordinates::Matrix phi;  // points x cage vertices
  GreenCoordinates::Matrix psi;  // points x cage faces
  // Points whose total solid angle says they lie outside the cage; their coordinates do not
  // reproduce them (Green coordinates as computed here are defined inside the cage only).
  std::vector<int> outsidePoints;
};

// Throws CageError unless `cage` is closed, 2-manifold, free of zero-area faces and outward
// oriented (positive signed volume). An inward-oriented cage is refused, not flipped: flipping
// would silently change which side the normals n(t_j) of the deformation point to.
void checkCage(const TriMesh& cage);

// phi and psi for points inside (or on) the cage: per face, the closed forms of the
// double-layer (phi, linear density) and single-layer (psi) potentials of LLCO08 section 3
// (what their Algorithm 1 evaluates through GCTriInt), written
// with a signed solid angle and per-edge log integrals so that points on a face, edge or vertex
// give their finite interior limits. Rows are independent; parallel over points, four points at
// a time in AVX2 vectors where the processor has them (each point near a face's plane on the
// scalar path that handles it exactly).
GreenCoordinatesResult computeGreenCoordinates(const TriMesh& cage,
                                               const std::vector<Eigen::Vector3d>& points,
                                               const GreenOptions& options = {});

// The same coordinates evaluated one (point, face) pair at a time from the cage's points, with
// no precomputed face or edge data and on one thread: the baseline and test oracle for
// computeGreenCoordinates (equal to it up to rounding). options.threads is ignored.
GreenCoordinatesResult computeGreenCoordinatesNaive(const TriMesh& cage,
                                                    const std::vector<Eigen::Vector3d>& points,
                                                    const GreenOptions& options = {});

// Per face of the deformed cage, LLCO08's stretch factor s_j: the scale of the face's map from
// the source cage, exact for similarities (s_j = lambda for a uniform scale lambda).
Eigen::VectorXd greenStretch(const TriMesh& sourceCage, const TriMesh& deformedCage);

// x' = sum_i phi_i v'_i + sum_j psi_j s_j n(t'_j) (LLCO08 section 3, with the stretch factors), one
// point per row of phi and psi. Throws CageError when the deformed cage's connectivity differs
// from the source cage's or when phi/psi do not fit the cage. Parallel over points on `threads`
// threads (0: every hardware thread), bit-identical for any count.
std::vector<Eigen::Vector3d> applyGreenCoordinates(const GreenCoordinates::Matrix& phi,
                                                   const GreenCoordinates::Matrix& psi,
                                                   const TriMesh& sourceCage,
                                                   const TriMesh& deformedCage, int threads = 0);

// The same for the points `rows` only (indices into phi and psi), in that order: what a brush
// needs of the draft is the region it pastes, and applying reads each row's coefficients, so the
// cost follows the rows asked for. Throws CageError as above, and for a row out of range.
std::vector<Eigen::Vector3d> applyGreenCoordinates(const GreenCoordinates::Matrix& phi,
                                                   const GreenCoordinates::Matrix& psi,
                                                   const TriMesh& sourceCage,
                                                   const TriMesh& deformedCage,
                                                   const std::vector<int>& rows, int threads = 0);

}  // namespace geobrush
