#include "geobrush/derived_store.hpp"

namespace geobrush {

std::shared_ptr<const void> DerivedStore::get(Hash key, const std::vector<ValuePtr>& derivedFrom,
                                              const Build& build) {
  {
    std::lock_guard lock(mutex_);
    if (auto it = entries_.find(key); it != entries_.end()) {
      it->second.lastUsed = generation_;
      return it->second.value;
    }
  }
  // Two threads may build the same entry at once; both builds are equal, the first one stays.
  std::shared_ptr<const void> built = build();
  std::lock_guard lock(mutex_);
  ++builds_;
  auto [it, inserted] = entries_.try_emplace(key, Entry{built, derivedFrom, generation_});
  it->second.lastUsed = generation_;
  return it->second.value;
}

void DerivedStore::nextGeneration() {
  std::lock_guard lock(mutex_);
  ++generation_;
  std::erase_if(entries_, [&](const auto& item) { return item.second.lastUsed + 1 < generation_; });
}

void DerivedStore::clear() {
  std::lock_guard lock(mutex_);
  entries_.clear();
}

std::size_t DerivedStore::size() const {
  std::lock_guard lock(mutex_);
  return entries_.size();
}

std::uint64_t DerivedStore::builds() const {
  std::lock_guard lock(mutex_);
  return builds_;
}

}  // namespace geobrush
