// Example-based completion (Freeform surface inpainting, section 6, after Bendels et al. 2005): a
// hole already closed by a smooth guidance patch gets fine detail copied from the rest of the
// mesh, scale by scale, coarsest first, rim inward.
//
// Mesh variant [ours]: the scale space is P^0 = the mesh and P^l = P^0 after 4^l steps of uniform
// Laplacian smoothing p <- p + (mean of the one-ring - p) / 2 (a Gaussian of width ~ 2^l edges,
// as the spec's h_l = 2 spacing 2^l). Level l's detail is the height of P^l over P^(l+1) along
// P^(l+1)'s area-weighted normal. A completed vertex v on level l gets the detail of the best
// candidate (an original vertex, under one of `rotations` turns about the normal) as a normal
// offset on the completed base P^(l+1); its descriptor is a tangent-plane height grid.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct FragmentCompleteOptions {
  int levels = 2;             // detail scales, completed coarsest first
  int descRes = 8;            // top-layer cells along a side; the bottom layer has half
  double radius = 0;          // descriptor half-width; 0: 4 x the mean edge length
  int rotations = 8;          // turns of each candidate about its normal
  double guidanceWeight = 1;  // weight of the guidance's own values in cells not yet known
  int candidateStride = 1;    // every n-th original vertex (in index order) is a candidate
  // Refused beyond these (FragmentCompleteError "candidate_stride") rather than run for minutes:
  double maxWork = 4e9;    // levels x completed x candidates x rotations x cells
  double maxStored = 5e7;  // candidate descriptor values (floats) held for one level
  int threads = 0;         // for the candidate descriptors; any count gives the same result
};

// The ceiling of a completed vertex's confidence: exactly what a perfect match (cost 0) gets.
inline constexpr double kCompletedConfidence = 0.5;

struct FragmentCompleteResult {
  TriMesh mesh;                    // the input's connectivity, completed vertices moved
  std::vector<double> confidence;  // per vertex: 1 original, (0, 0.5] completed
  std::size_t completed = 0;       // vertices completed
  std::size_t candidates = 0;      // candidate descriptors (vertex, rotation), on the finest level
  double meanBestCost = 0;  // the best cost (squared length), over matched vertices and levels
  double radius = 0;        // the descriptor half-width used
};

// A request that gives no completion; `option()` names the port or param to change ("mesh",
// "paste_map", "levels", "desc_res", "radius", "rotations", "guidance_weight",
// "candidate_stride").
class FragmentCompleteError : public std::invalid_argument {
 public:
  FragmentCompleteError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// The whole completion. `original[v]` != 0 marks the vertices kept as they are (confidence 1);
// the others are completed. Throws FragmentCompleteError.
FragmentCompleteResult fragmentComplete(const TriMesh& mesh,
                                        const std::vector<std::uint8_t>& original,
                                        const FragmentCompleteOptions& options);

// Stage functions, exposed for tests.

// P^0 .. P^levels of the scale space described above.
std::vector<std::vector<Eigen::Vector3d>> scaleSpace(const TriMesh& mesh, int levels);

// Unit area-weighted vertex normals of the mesh's connectivity at `points` (zero where every face
// around a vertex is degenerate).
std::vector<Eigen::Vector3d> areaWeightedNormals(const TriMesh& mesh,
                                                 const std::vector<Eigen::Vector3d>& points);

// The vertices not marked original, in rim-inward order: increasing number of edges to the
// nearest original vertex, ties by index; vertices no original one reaches come last, by index.
std::vector<int> rimInwardOrder(const TriMesh& mesh, const std::vector<std::uint8_t>& original);

// The confidence of a completed vertex whose best costs average `cost` (squared length):
// kCompletedConfidence exp(-sqrt(cost) / edge), decreasing with the cost, in (0, 0.5].
double completedConfidence(double cost, double edge);

}  // namespace geobrush
