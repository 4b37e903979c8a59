#include "variational_paste_cost.hpp"

#include <cmath>

namespace geobrush {
namespace {

Eigen::Matrix3d cross(const Eigen::Vector3d& a) {
  Eigen::Matrix3d m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

}  // namespace

RotatedPoint rotateWithJacobian(const Eigen::Vector3d& angleAxis, const Eigen::Vector3d& delta) {
  const double theta = angleAxis.norm(), t2 = theta * theta;
  const Eigen::Matrix3d w = cross(angleAxis), w2 = w * w;
  // a = sin t / t, b = (1 - cos t) / t^2, c = (t - sin t) / t^3. Below 0.01 rad their Taylor
  // series (the next terms are under 1e-21) avoid the cancellation in 1 - cos t and t - sin t.
  double a, b, c;
  if (theta < 1e-2) {
    a = 1 - t2 / 6 * (1 - t2 / 20 * (1 - t2 / 42));
    b = 0.5 - t2 / 24 * (1 - t2 / 30 * (1 - t2 / 56));
    c = 1.0 / 6 - t2 / 120 * (1 - t2 / 42 * (1 - t2 / 72));
  } else {
    const double half = std::sin(theta / 2);
    a = std::sin(theta) / theta;
    b = 2 * half * half / t2;
    c = (theta - std::sin(theta)) / (t2 * theta);
  }
  const Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity() + a * w + b * w2;
  const Eigen::Matrix3d rightJacobian = Eigen::Matrix3d::Identity() - b * w + c * w2;
  return {rotation * delta, -rotation * cross(delta) * rightJacobian};
}

LaplacianResidual::LaplacianResidual(std::vector<double> coefficients, double constant)
    : coefficients_(std::move(coefficients)), constant_(constant) {
  set_num_residuals(1);
  mutable_parameter_block_sizes()->assign(coefficients_.size(), 1);
}

LaplacianResidual::LaplacianResidual(std::vector<double> coefficients, double constant,
                                     const Eigen::Vector3d& delta, int coordinate)
    : LaplacianResidual(std::move(coefficients), constant) {
  rotated_ = true;
  delta_ = delta;
  coordinate_ = coordinate;
  mutable_parameter_block_sizes()->push_back(3);
}

bool LaplacianResidual::Evaluate(double const* const* parameters, double* residuals,
                                 double** jacobians) const {
  double r = constant_;
  for (std::size_t i = 0; i < coefficients_.size(); ++i)
    r += coefficients_[i] * parameters[i][0];
  RotatedPoint rotated;
  if (rotated_) {
    rotated = rotateWithJacobian(
        Eigen::Map<const Eigen::Vector3d>(parameters[coefficients_.size()]), delta_);
    r -= rotated.point[coordinate_];
  }
  residuals[0] = r;
  if (!jacobians) return true;
  for (std::size_t i = 0; i < coefficients_.size(); ++i)
    if (jacobians[i]) jacobians[i][0] = coefficients_[i];
  if (rotated_ && jacobians[coefficients_.size()]) {
    double* row = jacobians[coefficients_.size()];
    for (int j = 0; j < 3; ++j)
      row[j] = -rotated.jacobian(coordinate_, j);
  }
  return true;
}

}  // namespace geobrush
