// The transferred signal of EMD detail transfer, Eqs. 3-5 as one formula: on Q_t,
// g^ = r_m^t + sum_k b(k) h_k^t + sum_k a(k) H_k^s (b = 1: Eq. 3, the target's detail kept;
// b = 0: Eq. 5, replaced), the source modes H_k^s averaged at each target vertex (Eq. 4);
// elsewhere the target's own signal.
#pragma once

#include <vector>

namespace geobrush {

struct EmdTransferOptions {
  std::vector<double> gains;       // a(k), one per source mode: the equalizer
  std::vector<double> keepTarget;  // b(k), one per target mode
};

struct EmdTransferResult {
  std::vector<double> signal;  // g^ per target vertex
  std::vector<double> detail;  // d = sum_k a(k) H_k^s on Q_t, 0 elsewhere
};

// Columns are per target vertex and all of one length; `region` is 1 on Q_t, 0 elsewhere.
// Throws std::invalid_argument when a list's length is not its mode count or a column's length
// differs, naming which.
EmdTransferResult transferSignal(const std::vector<const std::vector<double>*>& targetModes,
                                 const std::vector<double>& targetResidue,
                                 const std::vector<const std::vector<double>*>& sourceModes,
                                 const std::vector<double>& region,
                                 const EmdTransferOptions& options);

}  // namespace geobrush
