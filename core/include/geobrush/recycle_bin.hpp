// Output values the framework has retired, kept for the node that made them to build its next
// result in (Context::recycle; see core/DESIGN.md).
#pragma once

#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <string_view>
#include <typeinfo>
#include <utility>

#include "geobrush/value.hpp"

namespace geobrush {

// A value a node published with Context::outRecyclable, and what the node said about it then.
struct RecyclableValue {
  ValuePtr value;
  std::shared_ptr<const void> note;
  const std::type_info* noteType = nullptr;
};

// One bin per evaluator. It keeps the newest kPerPort values retired from each node's output
// port; a value is handed back only where the bin's reference is the last one, so the node that
// takes it holds it alone (values are never watched through a std::weak_ptr, which could take
// hold of one again).
class RecycleBin {
 public:
  static constexpr std::size_t kPerPort = 1;

  void put(const std::string& node, const std::string& port, RecyclableValue retired);

  // The newest value of (node, port) that nothing else holds and whose note `accepts`, taken out
  // of the bin; an empty one where there is none. Values whose notes it refuses are dropped (a
  // note does not change: they would be refused again); values still held elsewhere stay.
  RecyclableValue take(const std::string& node, std::string_view port,
                       const std::function<bool(const RecyclableValue&)>& accepts);

  // Drops the values of every node not in `nodes` (a node removed from the graph).
  void keepNodes(const std::set<std::string>& nodes);
  void clear();
  std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, std::string>, std::deque<RecyclableValue>> bins_;
};

}  // namespace geobrush
