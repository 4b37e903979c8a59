// Data derived from node inputs (locators, factorizations, coordinates), kept by the framework
// between evaluations so that nodes keep none (see core/DESIGN.md).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <unordered_map>
#include <vector>

#include "geobrush/hash.hpp"
#include "geobrush/value.hpp"

namespace geobrush {

// One store per evaluator. An entry lives while the evaluations that use it are the current or
// the previous one (the lifetime of the evaluator's cached outputs), and keeps alive the input
// values it was derived from, so that derived data may refer into them.
class DerivedStore {
 public:
  using Build = std::function<std::shared_ptr<const void>()>;

  // The entry under `key`, built (outside the store's lock; safe from several threads) where
  // there is none. What `build` throws passes through and stores nothing.
  std::shared_ptr<const void> get(Hash key, const std::vector<ValuePtr>& derivedFrom,
                                  const Build& build);

  // Starts the next evaluation and drops what neither it nor the one before used.
  void nextGeneration();
  void clear();
  std::size_t size() const;
  // Entries built since construction (not found in the store).
  std::uint64_t builds() const;

 private:
  struct Entry {
    std::shared_ptr<const void> value;
    std::vector<ValuePtr> derivedFrom;
    std::uint64_t lastUsed = 0;
  };
  mutable std::mutex mutex_;
  std::unordered_map<Hash, Entry> entries_;
  std::uint64_t generation_ = 0;
  std::uint64_t builds_ = 0;
};

}  // namespace geobrush
