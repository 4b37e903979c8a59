// Runs one node outside any graph, for node-level tests: inputs given
// directly, params at their defaults unless set, outputs and warnings kept.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/derived_store.hpp"
#include "geobrush/node.hpp"
#include "geobrush/recycle_bin.hpp"

namespace geobrush::test {

class DirectContext final : public Context {
 public:
  // `derived`: where Context::derived keeps its data; contexts that share one reuse what an
  // earlier compute derived, as the evaluator's runs do. Null: a store of this context's own.
  // `bin`: where the outputs published as recyclable go when the context ends (an evaluator
  // retires them two runs later), for the next context's node to recycle; null: nowhere.
  DirectContext(const NodeType& type, std::map<std::string, ValuePtr, std::less<>> inputs,
                const ParamMap& params = {}, std::shared_ptr<DerivedStore> derived = nullptr,
                std::shared_ptr<RecycleBin> bin = nullptr);
  ~DirectContext() override;

  std::filesystem::path path(std::string_view) const override { return {}; }
  void out(std::string_view port, ValuePtr value) override;
  void progress(double) override {}
  bool cancelled() const override { return false; }
  void warn(const std::string& message) override { warnings.push_back(message); }
  // Node tests that write files go through the evaluator instead.
  void writeFile(const std::filesystem::path& path,
                 const std::function<void(const std::filesystem::path&)>&) override;

  std::map<std::string, ValuePtr, std::less<>> outputs;
  std::vector<std::string> warnings;

 protected:
  ValuePtr inputValue(std::string_view port) const override;
  const ParamValue& paramValue(std::string_view name) const override;
  // The content hash of the input: equal values, equal keys.
  Hash inputKey(std::string_view port) const override;
  std::shared_ptr<const void> derivedValue(
      Hash key, const std::vector<ValuePtr>& derivedFrom,
      const std::function<std::shared_ptr<const void>()>& build) override;
  void keepRecyclable(std::string_view port, RecyclableValue value) override;
  RecyclableValue recycledValue(
      std::string_view port, const std::function<bool(const RecyclableValue&)>& accepts) override;

 private:
  static constexpr const char* kNode = "node";  // the bin's name for the node
  std::shared_ptr<DerivedStore> derived_;
  std::shared_ptr<RecycleBin> bin_;
  std::map<std::string, RecyclableValue> recyclable_;
  std::map<std::string, ValuePtr, std::less<>> inputs_;
  std::map<std::string, ParamValue, std::less<>> params_;
};

// Computes `node` as the evaluator does: prepare(), then compute(), on the same context.
inline void run(Node& node, Context& ctx) {
  node.prepare(ctx);
  node.compute(ctx);
}
inline void run(std::unique_ptr<Node> node, Context& ctx) {
  run(*node, ctx);
}

// What one run of a registered node type left: its outputs and warnings.
struct NodeRun {
  std::map<std::string, ValuePtr, std::less<>> outputs;
  std::vector<std::string> warnings;
  // The output on `port` as a T; null when it is missing or of another type.
  template <ValueType T>
  std::shared_ptr<const T> get(std::string_view port) const {
    const auto it = outputs.find(port);
    return it == outputs.end() ? nullptr : std::dynamic_pointer_cast<const T>(it->second);
  }
};

// Runs the node type `id` of registry() (every plugin of the build) once on a fresh instance, as
// the evaluator does; what it throws passes through.
NodeRun runNode(const std::string& id, std::map<std::string, ValuePtr, std::less<>> inputs,
                const ParamMap& params = {});

}  // namespace geobrush::test
