#include "geobrush/recycle_bin.hpp"

#include <algorithm>

namespace geobrush {

void RecycleBin::put(const std::string& node, const std::string& port, RecyclableValue retired) {
  std::lock_guard lock(mutex_);
  auto& bin = bins_[{node, port}];
  bin.push_back(std::move(retired));
  while (bin.size() > kPerPort)
    bin.pop_front();
}

RecyclableValue RecycleBin::take(const std::string& node, std::string_view port,
                                 const std::function<bool(const RecyclableValue&)>& accepts) {
  std::lock_guard lock(mutex_);
  auto found = bins_.find({node, std::string(port)});
  if (found == bins_.end()) return {};
  auto& bin = found->second;
  RecyclableValue taken;
  // Newest first: the likeliest to have been made from what the node is given now.
  for (auto it = bin.end(); it != bin.begin() && !taken.value;) {
    --it;
    // The bin's reference is the only one: no one else can take hold of the value again.
    if (it->value.use_count() != 1) continue;
    if (accepts(*it)) taken = std::move(*it);
    it = bin.erase(it);
  }
  if (bin.empty()) bins_.erase(found);
  return taken;
}

void RecycleBin::keepNodes(const std::set<std::string>& nodes) {
  std::lock_guard lock(mutex_);
  std::erase_if(bins_, [&](const auto& item) { return !nodes.count(item.first.first); });
}

void RecycleBin::clear() {
  std::lock_guard lock(mutex_);
  bins_.clear();
}

std::size_t RecycleBin::size() const {
  std::lock_guard lock(mutex_);
  std::size_t count = 0;
  for (const auto& [key, bin] : bins_)
    count += bin.size();
  return count;
}

}  // namespace geobrush
