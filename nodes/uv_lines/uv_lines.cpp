#include "uv_lines.hpp"

#include <cmath>
#include <stdexcept>

namespace geobrush {
namespace {

// Distance from x to the nearest multiple of `spacing`, as a fraction of it.
double offLine(double x, double spacing) {
  const double t = x / spacing;
  return std::abs(t - std::round(t));
}

}  // namespace

UvLinesResult paintUvLines(const Parameterization& param, const UvLinesOptions& options) {
  if (!param.canvas || param.uv.size() != param.canvas->surface.n_vertices())
    throw std::invalid_argument("the parameterization does not match its canvas");
  if (!(options.width > 0 && options.width < 1))
    throw std::invalid_argument("the line width must be in (0, 1)");
  UvLinesResult result;
  result.spacing = options.spacing;
  if (result.spacing <= 0) {
    Eigen::Vector2d lo = param.uv.front(), hi = param.uv.front();
    for (const auto& p : param.uv) {
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
    result.spacing = std::max((hi - lo).maxCoeff(), 1e-12) / 10;
  }
  result.mesh.surface = param.canvas->surface;
  result.mesh.vertexColors.reserve(param.uv.size());
  const double half = options.width / 2;
  for (const auto& p : param.uv) {
    if (!p.allFinite()) throw std::invalid_argument("the parameterization has a non-finite uv");
    // Where a u line and a v line cross, the u line wins: the choice only
    // needs to be the same everywhere.
    if (offLine(p.x(), result.spacing) <= half)
      result.mesh.vertexColors.push_back(options.uLine);
    else if (offLine(p.y(), result.spacing) <= half)
      result.mesh.vertexColors.push_back(options.vLine);
    else
      result.mesh.vertexColors.push_back(options.surface);
  }
  return result;
}

}  // namespace geobrush
