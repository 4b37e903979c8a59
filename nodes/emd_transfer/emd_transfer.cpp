#include "emd_transfer.hpp"

#include <stdexcept>
#include <string>

namespace geobrush {
namespace {

void checkLengths(const std::vector<const std::vector<double>*>& targetModes,
                  const std::vector<const std::vector<double>*>& sourceModes,
                  const std::vector<double>& region, const EmdTransferOptions& options) {
  if (options.gains.size() != sourceModes.size())
    throw std::invalid_argument("gains has " + std::to_string(options.gains.size()) +
                                " entries for " + std::to_string(sourceModes.size()) +
                                " source modes");
  if (options.keepTarget.size() != targetModes.size())
    throw std::invalid_argument("keep_target has " + std::to_string(options.keepTarget.size()) +
                                " entries for " + std::to_string(targetModes.size()) +
                                " target modes");
  for (const auto* column : targetModes)
    if (column->size() != region.size())
      throw std::invalid_argument("a target mode's length differs from the region's");
  for (const auto* column : sourceModes)
    if (column->size() != region.size())
      throw std::invalid_argument("a sampled source mode's length differs from the region's");
}

}  // namespace

EmdTransferResult transferSignal(const std::vector<const std::vector<double>*>& targetModes,
                                 const std::vector<double>& targetResidue,
                                 const std::vector<const std::vector<double>*>& sourceModes,
                                 const std::vector<double>& region,
                                 const EmdTransferOptions& options) {
  checkLengths(targetModes, sourceModes, region, options);
  if (targetResidue.size() != region.size())
    throw std::invalid_argument("the target residue's length differs from the region's");
  EmdTransferResult result;
  result.signal = targetResidue;
  result.detail.assign(region.size(), 0.0);
  for (std::size_t v = 0; v < region.size(); ++v) {
    const bool inside = region[v] != 0.0;
    for (std::size_t k = 0; k < targetModes.size(); ++k)
      result.signal[v] += (inside ? options.keepTarget[k] : 1.0) * (*targetModes[k])[v];
    if (!inside) continue;
    for (std::size_t k = 0; k < sourceModes.size(); ++k)
      result.detail[v] += options.gains[k] * (*sourceModes[k])[v];
    result.signal[v] += result.detail[v];
  }
  return result;
}

}  // namespace geobrush
