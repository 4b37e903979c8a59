// A valid param value other than the default, for tests that change every param of a node.
#pragma once

#include <algorithm>
#include <cmath>

#include "geobrush/param.hpp"

namespace geobrush::test {

// A value different from the default that is still valid for the declaration.
inline ParamValue perturbed(const ParamDecl& decl) {
  auto fit = [&](double v, double fallback) {
    if ((decl.min && v < *decl.min) || (decl.max && v > *decl.max)) return fallback;
    return v;
  };
  switch (decl.kind) {
    case ParamKind::Bool:
      return !std::get<bool>(decl.defaultValue);
    case ParamKind::Int: {
      auto v = std::get<std::int64_t>(decl.defaultValue);
      return std::int64_t(fit(double(v + 1), double(v - 1)));
    }
    case ParamKind::Double: {
      double v = std::get<double>(decl.defaultValue);
      double up = v + 0.25 * std::max(1e-3, std::abs(v));
      double down = v - 0.25 * std::max(1e-3, std::abs(v));
      return fit(up, down);
    }
    case ParamKind::String:
    case ParamKind::InputPath:
    case ParamKind::OutputPath: {
      std::string v = std::get<std::string>(decl.defaultValue);
      return v.empty() ? std::string("other") : "other_" + v;
    }
    case ParamKind::Enum:
      for (const auto& choice : decl.choices)
        if (choice != std::get<std::string>(decl.defaultValue)) return choice;
      return decl.defaultValue;
    case ParamKind::Vec3: {
      Vec3 v = std::get<Vec3>(decl.defaultValue);
      for (double& x : v)
        x = fit(x + 0.5, x - 0.5);
      return v;
    }
    case ParamKind::DoubleList: {
      auto v = std::get<std::vector<double>>(decl.defaultValue);
      double x = decl.min ? *decl.min : (decl.max ? *decl.max : 0.5);
      for (int i = 0; i < decl.rowSize; ++i)
        v.push_back(x);
      return v;
    }
  }
  return decl.defaultValue;
}

}  // namespace geobrush::test
