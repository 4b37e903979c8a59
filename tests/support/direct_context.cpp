#include "direct_context.hpp"

#include <stdexcept>

#include "test_support.hpp"

namespace geobrush::test {

DirectContext::DirectContext(const NodeType& type,
                             std::map<std::string, ValuePtr, std::less<>> inputs,
                             const ParamMap& params, std::shared_ptr<DerivedStore> derived,
                             std::shared_ptr<RecycleBin> bin)
    : derived_(derived ? std::move(derived) : std::make_shared<DerivedStore>()),
      bin_(std::move(bin)),
      inputs_(std::move(inputs)) {
  for (const auto& decl : type.params)
    params_[decl.name] = decl.defaultValue;
  for (const auto& [name, value] : params)
    params_[name] = value;
}

DirectContext::~DirectContext() {
  if (!bin_) return;
  for (auto& [port, value] : recyclable_)
    bin_->put(kNode, port, std::move(value));
}

void DirectContext::out(std::string_view port, ValuePtr value) {
  outputs[std::string(port)] = std::move(value);
  recyclable_.erase(std::string(port));  // outRecyclable keeps it again
}

void DirectContext::writeFile(const std::filesystem::path& path,
                              const std::function<void(const std::filesystem::path&)>&) {
  throw std::logic_error("DirectContext writes no files (asked for " + path.string() + ")");
}

ValuePtr DirectContext::inputValue(std::string_view port) const {
  const auto it = inputs_.find(port);
  return it == inputs_.end() ? nullptr : it->second;
}

const ParamValue& DirectContext::paramValue(std::string_view name) const {
  const auto it = params_.find(name);
  if (it == params_.end()) throw NodeError::param(name, "is not declared");
  return it->second;
}

Hash DirectContext::inputKey(std::string_view port) const {
  const ValuePtr value = inputValue(port);
  return value ? value->contentHash() : 0;
}

std::shared_ptr<const void> DirectContext::derivedValue(
    Hash key, const std::vector<ValuePtr>& derivedFrom,
    const std::function<std::shared_ptr<const void>()>& build) {
  return derived_->get(key, derivedFrom, build);
}

void DirectContext::keepRecyclable(std::string_view port, RecyclableValue value) {
  recyclable_[std::string(port)] = std::move(value);
}

RecyclableValue DirectContext::recycledValue(
    std::string_view port, const std::function<bool(const RecyclableValue&)>& accepts) {
  return bin_ ? bin_->take(kNode, port, accepts) : RecyclableValue{};
}

NodeRun runNode(const std::string& id, std::map<std::string, ValuePtr, std::less<>> inputs,
                const ParamMap& params) {
  const NodeType* type = registry().find(id);
  if (!type) throw std::logic_error("no node type " + id + " is registered");
  DirectContext ctx(*type, std::move(inputs), params);
  run(type->create(), ctx);
  return {std::move(ctx.outputs), std::move(ctx.warnings)};
}

}  // namespace geobrush::test
