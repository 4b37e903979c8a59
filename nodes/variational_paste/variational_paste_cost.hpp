// The residuals of the variational paste (variational_paste.hpp) as Ceres cost functions with
// hand-written Jacobians: the solver evaluates them once per iteration on every vertex, where
// automatic differentiation over a one-ring of varying size would cost several times more.
#pragma once

#include <Eigen/Core>
#include <vector>

#include <ceres/cost_function.h>

namespace geobrush {

// One coordinate k of the Laplacian residual of one vertex v (one row, so that the three
// coordinates' normal equations stay apart: see variational_paste.cpp):
//   r = sum_i a_i x_i + b - [R(w) d]_k
// over the scalar parameter blocks x_i (coordinate k of v and of its free neighbours) with the
// Laplacian's coefficients a_i; b gathers the fixed neighbours and, without a rotation, -d_k.
// With a rotation, the last parameter block is the angle-axis vector w (3 values) of v's local
// rotation and d its Laplacian coordinate in the draft (ceres::AngleAxisRotatePoint's
// convention). The same form, with coefficients (s, -s) and d = s (g_w - g_v), is the ring-fit
// term s ((x_w - x_v) - R(w) (g_w - g_v)) that ties v's rotation to its one-ring edges.
class LaplacianResidual final : public ceres::CostFunction {
 public:
  // Without a rotation: r = sum_i a_i x_i + b.
  LaplacianResidual(std::vector<double> coefficients, double constant);
  // With a rotation of `delta`, coordinate `coordinate` (0, 1 or 2).
  LaplacianResidual(std::vector<double> coefficients, double constant, const Eigen::Vector3d& delta,
                    int coordinate);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

 private:
  std::vector<double> coefficients_;
  double constant_;
  bool rotated_ = false;
  Eigen::Vector3d delta_ = Eigen::Vector3d::Zero();
  int coordinate_ = 0;
};

// R(w) d and its derivative with respect to w (3 x 3), by Rodrigues' formula and the right
// Jacobian of SO(3): d(R(w) d)/dw = -R(w) [d]x J_r(w). Exposed for tests.
struct RotatedPoint {
  Eigen::Vector3d point;
  Eigen::Matrix3d jacobian;
};
RotatedPoint rotateWithJacobian(const Eigen::Vector3d& angleAxis, const Eigen::Vector3d& delta);

}  // namespace geobrush
