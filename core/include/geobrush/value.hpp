// Immutable values that flow between nodes.
#pragma once

#include <memory>
#include <string>
#include <string_view>

#include "geobrush/hash.hpp"

namespace geobrush {

// Base of every value type. A value is immutable once shared: nodes receive
// std::shared_ptr<const T> and copy before changing anything. (Only the node that made a value
// may change it again, once the framework hands it back to it held by no one else:
// Context::recycle.)
class Value {
 public:
  virtual ~Value() = default;
  // Stable string id of the concrete type, e.g. "geobrush.Mesh".
  virtual std::string_view typeId() const = 0;
  // Hash of the content; equal content gives equal hashes.
  virtual Hash contentHash() const = 0;
  // One line for reports and the studio, e.g. "mesh: 1839 vertices, 3674 faces".
  virtual std::string summary() const = 0;
};

using ValuePtr = std::shared_ptr<const Value>;

// Every value type T has `static constexpr std::string_view kTypeId`.
template <typename T>
concept ValueType = std::is_base_of_v<Value, T> && requires {
  { T::kTypeId } -> std::convertible_to<std::string_view>;
};

}  // namespace geobrush
