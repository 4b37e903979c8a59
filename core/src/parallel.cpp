#include "geobrush/parallel.hpp"

namespace geobrush::detail {

bool& serialThread() {
  thread_local bool serial = false;
  return serial;
}

}  // namespace geobrush::detail
