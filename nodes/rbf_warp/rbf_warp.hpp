// The template warp of surface inpainting (Freeform surface inpainting, section 4.2): an aligned
// template T' is displaced so that its paired vertices t_b_i land on the hole's border points b_i
// (generalised constraints, Eqs. 3-6, Gaussian RBFs over the kNN-graph geodesic), then cropped
// to the part on the hole's side of the line L through the t_b_i [ours: the paper leaves the
// crop unspecified].
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/geodesic_rbf.hpp"
#include "geobrush/knn_graph.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/point_pairs.hpp"

namespace geobrush {

struct RbfWarpOptions {
  int k = 8;         // kNN graph neighbours for delta (section 5.1; k unstated, 8 as gdem [ours])
  double tMax = 0;   // Eq. 5's width; 0: the template's bounding-box diagonal [paper]
  double reg = 0;    // eigenvalues moved off 0 by reg, Eq. 6 (GeodesicRbfOptions::reg) [ours]
  int stride = 1;    // every stride-th pair is a constraint: thins dense constraints [ours]
  bool crop = true;  // keep the template's part on the hole side of L [ours]
  // Lay the cropped boundary L onto the border polyline (corners on the b_i, the path between
  // spread along the segments) [ours]: what lets the weld share every seam vertex.
  bool snapBoundary = true;
  // With tMax = 0: t_max the border's radius (the mean distance of the b_i from their centroid)
  // instead of the template's diagonal [ours]: a kernel the size of the hole, well conditioned.
  bool tMaxFromBorder = false;
  // delta as the straight distance between template vertices instead of the kNN graph's
  // (GeodesicRbfOptions::straightPoints) [ours]: for flat or gently curved templates.
  bool straightDistance = false;
  // phi: the paper's Gaussian, or SCODEF's compact cubic for comparison (RbfKernel).
  RbfKernel kernel = RbfKernel::Gaussian;
};

// An input that gives no warp. `option()` names the input to change: "template" or "pairs".
class RbfWarpError : public std::invalid_argument {
 public:
  RbfWarpError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

struct RbfWarpResult {
  TriMesh mesh;                   // T'': the warped template, cropped when asked
  std::vector<int> sourceVertex;  // mesh vertex -> template vertex, increasing
  // d(x) = d_h(x) per template vertex (Eq. 3 with alpha = 1 [ours], Eq. 4).
  std::vector<Eigen::Vector3d> displacement;
  std::vector<int> constraintPair;  // the pairs used as constraints, increasing
  int duplicatesDropped = 0;  // strided pairs whose template vertex an earlier constraint took
  double tMax = 0;
  double conditionNumber = 0;      // cond of A with reg (GeodesicRbfResult), 2-norm
  double bboxDiagonal = 0;         // the template's; residuals are relative to it
  double maxResidual = 0;          // max |t''_b_i - b_i| / bboxDiagonal over the constraints
  double maxResidualAllPairs = 0;  // the same over every pair
  int constraintsKept = 0;         // constraints whose vertex the crop keeps
};

// Throws RbfWarpError("pairs") unless every pair has a finite border point and a template
// vertex of `mesh`, and there are as many of each; RbfWarpError("template") for a mesh without
// faces.
void requireValidInputs(const TriMesh& mesh, const PointPairs& pairs);

// The pairs that constrain the warp: every stride-th, minus those whose template vertex an
// earlier one already constrains (two displacements for one vertex cannot both hold; their count
// goes to `dropped`). Throws RbfWarpError("pairs") with fewer than 3.
std::vector<int> constraintPairs(const PointPairs& pairs, int stride, int& dropped);

// The shortest edge paths of `mesh` between consecutive vertices of `loop` (the last back to the
// first), each as its halfedges in order. Throws RbfWarpError("pairs") where two are not
// connected.
std::vector<std::vector<TriMesh::HalfedgeHandle>> pathSegments(const TriMesh& mesh,
                                                               const std::vector<int>& loop);

// L: the template's edges on the closed path through the t_b_i in pair order, each consecutive
// two (distinct) joined by a shortest edge path of `mesh` (Dijkstra, Euclidean edge lengths, ties
// broken the same way on every run); an edge the path takes twice (there and back) is a spur and
// not on L. One flag per edge. Throws RbfWarpError("pairs") where two are not connected.
std::vector<char> pathEdges(const TriMesh& mesh, const std::vector<int>& loop);

// The faces reached from `seed` through edges not on L, increasing. Throws RbfWarpError("pairs")
// when L does not separate them: an edge of L with reached faces on both sides (the flood went
// round it). Where L runs along the mesh boundary alone, every face is kept.
std::vector<int> floodFaces(const TriMesh& mesh, const std::vector<char>& onL, int seed);

// Warps (Eqs. 3-6) and crops `mesh` given its kNN graph (over vertexPoints(mesh), options.k).
// The crop is found on `mesh` before the warp and applied to the warped template: L through every
// pair's t_b_i (not only the constraints), flooded from the face nearest the centroid of the b_i.
// Throws RbfWarpError.
RbfWarpResult rbfWarp(const TriMesh& mesh, const KnnGraph& graph, const PointPairs& pairs,
                      const RbfWarpOptions& options = {});

}  // namespace geobrush
