// Displacements interpolated by Gaussian radial basis functions over the geodesic distance of a
// kNN graph (Freeform surface inpainting, section 4.2, Eqs. 4-6): the warp of a template onto a
// hole's border and the non-rigid handle edit both propagate per-constraint translations this way.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <span>
#include <vector>

#include "geobrush/knn_graph.hpp"

namespace geobrush {

// phi of Eq. 4: the paper's Gaussian (Eq. 5), or SCODEF's cubic (Borrel and Rappoport 1994, the
// shape functions of Eqs. 1-2 that the paper starts from): 1 - 3s^2 + 2s^3 of s = t / t_max, 0
// from t_max on, so each constraint reaches a ball of radius t_max; for comparison.
enum class RbfKernel { Gaussian, Scodef };

struct GeodesicRbfOptions {
  RbfKernel kernel = RbfKernel::Gaussian;
  double tMax = 1.0;  // phi(t) = exp(-(t / t_max)^2), Eq. 5; the paper takes the bbox diagonal
  // Tikhonov term [ours]: the paper's t_max makes A near-singular for dense constraints. A
  // Gaussian of graph distances is in general indefinite (the graph metric is no Euclidean one),
  // and reg on the diagonal would push a negative eigenvalue toward 0; so reg moves every
  // eigenvalue away from 0 by reg, keeping its sign: A + reg sign(A), plain A + reg I where A is
  // positive definite. The condition number then always drops, and the constraints hold up to
  // reg |D_i|.
  double reg = 0.0;
  // The graph's points [ours]: when given, delta is the straight distance between them rather
  // than the graph's. On a flat or gently curved template the two agree but for the graph's
  // direction error (up to 8% with k = 8), which the near-singular A of the paper's t_max turns
  // into displacement noise; the straight distance gives a smooth interpolant.
  std::span<const Eigen::Vector3d> straightPoints = {};
};

struct GeodesicRbfResult {
  // d_h(x) of Eq. 4 at every graph point; 0 where no constraint reaches (another component).
  std::vector<Eigen::Vector3d> displacement;
  Eigen::MatrixXd system;         // A_ij = phi(delta(c_i, c_j)) (Eq. 6), symmetrised
  Eigen::MatrixX3d weights;       // D: the partial displacements solving (A + reg sign(A)) D = d
  double conditionNumber = 0;     // of A + reg sign(A): (max |lambda| + reg) / (min |lambda| + reg)
  double smallestEigenvalue = 0;  // A's, signed
  double largestEigenvalue = 0;
};

// The Gaussian kernel of Eq. 5.
inline double gaussianRbf(double t, double tMax) {
  const double s = t / tMax;
  return std::exp(-s * s);
}

// SCODEF's shape function, 0 from `radius` on.
inline double scodefRbf(double t, double radius) {
  const double s = t / radius;
  return s >= 1 ? 0.0 : 1 - s * s * (3 - 2 * s);
}

// Interpolates `displacement[i]` at graph vertex `constraint[i]` (distinct vertices) over the
// whole graph: one Dijkstra per constraint gives delta, A is solved through its eigenvectors (it is
// symmetric but not always positive definite), and
// d_h is summed in constraint order, so results are bit-identical on every run. Distances beyond
// the one where phi underflows to 0 are not explored, which changes no value. Throws
// std::invalid_argument for mismatched sizes, no constraint, a repeated or out-of-range vertex,
// a non-finite displacement, t_max <= 0 or reg < 0.
GeodesicRbfResult geodesicRbf(const KnnGraph& graph, std::span<const int> constraint,
                              std::span<const Eigen::Vector3d> displacement,
                              const GeodesicRbfOptions& options = {});

}  // namespace geobrush
