#include "geobrush/node.hpp"

#include <algorithm>

namespace geobrush {
namespace {

template <typename T>
const T* findByName(const std::vector<T>& items, std::string_view name) {
  auto it =
      std::find_if(items.begin(), items.end(), [&](const T& item) { return item.name == name; });
  return it == items.end() ? nullptr : &*it;
}

// Adapts a plain function to a stateless node.
class FunctionNode final : public Node {
 public:
  explicit FunctionNode(std::function<void(Context&)> fn) : fn_(std::move(fn)) {}
  void compute(Context& ctx) override { fn_(ctx); }

 private:
  std::function<void(Context&)> fn_;
};

ParamDecl makeParam(std::string name, ParamKind kind, ParamValue value, std::string doc) {
  ParamDecl decl;
  decl.name = std::move(name);
  decl.kind = kind;
  decl.defaultValue = std::move(value);
  decl.doc = std::move(doc);
  return decl;
}

}  // namespace

const PortDecl* NodeType::findInput(std::string_view name) const {
  return findByName(inputs, name);
}
const PortDecl* NodeType::findOutput(std::string_view name) const {
  return findByName(outputs, name);
}
const ParamDecl* NodeType::findParam(std::string_view name) const {
  return findByName(params, name);
}

bool NodeType::writesFiles() const {
  return std::any_of(params.begin(), params.end(),
                     [](const ParamDecl& p) { return p.kind == ParamKind::OutputPath; });
}

NodeTypeBuilder::NodeTypeBuilder(std::string id, int version) {
  type_.id = std::move(id);
  type_.version = version;
}

NodeTypeBuilder& NodeTypeBuilder::label(std::string text) {
  type_.label = std::move(text);
  return *this;
}
NodeTypeBuilder& NodeTypeBuilder::category(std::string text) {
  type_.category = std::move(text);
  return *this;
}
NodeTypeBuilder& NodeTypeBuilder::doc(std::string text) {
  type_.doc = std::move(text);
  return *this;
}

NodeTypeBuilder& NodeTypeBuilder::addParam(ParamDecl decl) {
  type_.params.push_back(std::move(decl));
  return *this;
}

NodeTypeBuilder& NodeTypeBuilder::paramBool(std::string name, bool value, std::string doc) {
  return addParam(makeParam(std::move(name), ParamKind::Bool, value, std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramInt(std::string name, std::int64_t value, std::string doc) {
  return addParam(makeParam(std::move(name), ParamKind::Int, value, std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramDouble(std::string name, double value, std::string doc) {
  return addParam(makeParam(std::move(name), ParamKind::Double, value, std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramString(std::string name, std::string value,
                                              std::string doc) {
  return addParam(makeParam(std::move(name), ParamKind::String, std::move(value), std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramEnum(std::string name, std::string value,
                                            std::vector<std::string> choices, std::string doc) {
  ParamDecl decl = makeParam(std::move(name), ParamKind::Enum, std::move(value), std::move(doc));
  decl.choices = std::move(choices);
  return addParam(std::move(decl));
}
NodeTypeBuilder& NodeTypeBuilder::paramInputPath(std::string name, std::string doc) {
  return addParam(makeParam(std::move(name), ParamKind::InputPath, std::string(), std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramOutputPath(std::string name, std::string value,
                                                  std::string doc) {
  return addParam(
      makeParam(std::move(name), ParamKind::OutputPath, std::move(value), std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramVec3(std::string name, Vec3 value, std::string doc) {
  return addParam(makeParam(std::move(name), ParamKind::Vec3, value, std::move(doc)));
}
NodeTypeBuilder& NodeTypeBuilder::paramList(std::string name, int rowSize,
                                            std::vector<double> value, std::string doc) {
  ParamDecl decl =
      makeParam(std::move(name), ParamKind::DoubleList, std::move(value), std::move(doc));
  decl.rowSize = rowSize;
  return addParam(std::move(decl));
}

NodeTypeBuilder& NodeTypeBuilder::range(double min, double max) {
  if (!type_.params.empty()) {
    type_.params.back().min = min;
    type_.params.back().max = max;
  }
  return *this;
}

NodeTypeBuilder& NodeTypeBuilder::compute(std::function<void(Context&)> fn) {
  type_.create = [fn = std::move(fn)] { return std::make_unique<FunctionNode>(fn); };
  return *this;
}

NodeTypeBuilder& NodeTypeBuilder::upgrade(int fromVersion, UpgradeFn fn) {
  type_.upgrades[fromVersion] = std::move(fn);
  return *this;
}

NodeTypeBuilder& NodeTypeBuilder::prepares(std::vector<std::string> inputs) {
  type_.prepareInputs = std::move(inputs);
  return *this;
}

NodeType NodeTypeBuilder::build() const {
  for (const std::string& input : type_.prepareInputs)
    if (!type_.findInput(input))
      throw std::invalid_argument("node type '" + type_.id + "' prepares from '" + input +
                                  "', which is not one of its inputs");
  return type_;
}

}  // namespace geobrush
