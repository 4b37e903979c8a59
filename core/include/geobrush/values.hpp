// Small value types: scalars, 3-vectors and metrics.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "geobrush/value.hpp"

namespace geobrush {

class Scalar final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Scalar";
  explicit Scalar(double value = 0.0) : value(value) {}
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;
  double value;
};

class Vector3 final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Vector3";
  explicit Vector3(std::array<double, 3> value = {0, 0, 0}) : value(value) {}
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;
  std::array<double, 3> value;
};

// Named measurements (sorted by name, so reports are stable) plus notes.
class Metrics final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.Metrics";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;
  std::map<std::string, double> values;
  std::vector<std::string> notes;
};

}  // namespace geobrush
