// The membrane with G = 0 over a planar triangulation, for fills.
#pragma once

#include <array>
#include <vector>

#include <Eigen/Core>
#include <Eigen/SparseCore>

namespace geobrush {

// Points are ordered: the unknowns first, then the known points whose rings are whole (the
// hole's border), then the known ring outside it, whose heights give the slopes.
struct MembraneProblem {
  int pointCount = 0;
  std::vector<std::array<int, 3>> triangles;  // oriented alike
  // Each triangle's corners, whose angles and areas weigh the operators: the chart's for the
  // patch, or the surface's.
  std::vector<std::array<Eigen::Vector3d, 3>> corners;
  Eigen::MatrixXd values;  // a row per point, a column per function; unknowns' rows are ignored
  int unknownCount = 0;
  int completeCount = 0;  // unknowns plus the border
  int continuity = 1;     // 0: L h = 0, 1: L M^-1 L h = 0 at the unknowns
};

// The unknown points' rows of the values. Throws std::runtime_error when the system is singular.
Eigen::MatrixXd solveMembrane(const MembraneProblem& problem);

}  // namespace geobrush
