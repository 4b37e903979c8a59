#include "geobrush/values.hpp"

#include <cstdio>

namespace geobrush {

Hash Scalar::contentHash() const {
  return Hasher().str(kTypeId).f64(value).digest();
}

std::string Scalar::summary() const {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

Hash Vector3::contentHash() const {
  return Hasher().str(kTypeId).f64(value[0]).f64(value[1]).f64(value[2]).digest();
}

std::string Vector3::summary() const {
  char text[128];
  std::snprintf(text, sizeof text, "(%.17g, %.17g, %.17g)", value[0], value[1], value[2]);
  return text;
}

Hash Metrics::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(values.size());
  for (const auto& [name, value] : values)
    hasher.str(name).f64(value);
  hasher.u64(notes.size());
  for (const auto& note : notes)
    hasher.str(note);
  return hasher.digest();
}

std::string Metrics::summary() const {
  return std::to_string(values.size()) + " metrics, " + std::to_string(notes.size()) + " notes";
}

}  // namespace geobrush
