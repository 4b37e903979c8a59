// The node API: declaring a node type and computing through a context.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include "geobrush/hash.hpp"
#include "geobrush/param.hpp"
#include "geobrush/recycle_bin.hpp"
#include "geobrush/value.hpp"

namespace geobrush {

// A failure inside a node. `where` names the port or parameter it concerns
// ("input 'mesh'", "param 'path'"), or is empty; the evaluator adds the
// graph file and the node name.
class NodeError : public std::runtime_error {
 public:
  NodeError(std::string where, const std::string& message)
      : std::runtime_error(message), where_(std::move(where)) {}
  explicit NodeError(const std::string& message) : std::runtime_error(message) {}

  static NodeError input(std::string_view port, const std::string& message) {
    return NodeError("input '" + std::string(port) + "'", message);
  }
  static NodeError output(std::string_view port, const std::string& message) {
    return NodeError("output '" + std::string(port) + "'", message);
  }
  static NodeError param(std::string_view name, const std::string& message) {
    return NodeError("param '" + std::string(name) + "'", message);
  }

  const std::string& where() const { return where_; }

 private:
  std::string where_;
};

// Thrown by Context::throwIfCancelled when the host cancels an evaluation.
class Cancelled : public std::runtime_error {
 public:
  Cancelled() : std::runtime_error("cancelled") {}
};

// A value a node takes back from the framework to build a new result in (Context::recycle), with
// the note it published it with.
template <ValueType T, typename Note>
struct Recycled {
  std::shared_ptr<T> value;
  std::shared_ptr<const Note> note;
  explicit operator bool() const { return value != nullptr; }
};

// What a node sees while it computes.
class Context {
 public:
  virtual ~Context() = default;

  // The value on an input port; throws NodeError if it is missing (only
  // possible for optional inputs) or of another type.
  template <ValueType T>
  std::shared_ptr<const T> in(std::string_view port) const {
    auto value = std::dynamic_pointer_cast<const T>(inputValue(port));
    if (!value) throw NodeError::input(port, "expected a " + std::string(T::kTypeId));
    return value;
  }
  bool hasInput(std::string_view port) const { return inputValue(port) != nullptr; }

  // A parameter's value, converted to T (bool, int, std::int64_t, double,
  // std::string, Vec3, std::vector<double>).
  template <typename T>
  T param(std::string_view name) const;
  // An InputPath or OutputPath parameter resolved to an absolute path.
  virtual std::filesystem::path path(std::string_view name) const = 0;

  virtual void out(std::string_view port, ValuePtr value) = 0;

  // Progress of this node in [0, 1]; shown on a terminal and in the studio.
  virtual void progress(double fraction) = 0;
  virtual bool cancelled() const = 0;
  void throwIfCancelled() const {
    if (cancelled()) throw Cancelled();
  }
  // A problem that was handled (e.g. what a repair changed); shown to the user.
  virtual void warn(const std::string& message) = 0;

  // Writes an output file as part of the evaluation's transaction: `write`
  // fills a temporary path in the same folder, and the file replaces `path`
  // only when the whole evaluation succeeds. A failed run leaves no file.
  virtual void writeFile(const std::filesystem::path& path,
                         const std::function<void(const std::filesystem::path& tmp)>& write) = 0;

  // Data derived from some of the inputs that costs more than a compute should repeat (a
  // locator, a factorization, coordinates): the framework keeps it while evaluations use it,
  // keyed by `what` (names the derivation: equal names build equal data), the framework's keys of
  // the values on `ports`, and `extra` (the params the derivation reads), and calls `build`
  // where it has none. Nodes of any type asking for the same key share one copy. `build` returns
  // a std::shared_ptr<const T> (or <T>); it may refer into the values on `ports`, which live as
  // long as the entry.
  template <typename Build>
  auto derived(std::string_view what, std::initializer_list<std::string_view> ports, Hash extra,
               const Build& build) {
    Hasher key = derivedKey<Build>(what, extra);
    std::vector<ValuePtr> from;
    for (std::string_view port : ports) {
      key.u64(inputKey(port));
      from.push_back(inputValue(port));
    }
    return derivedUnder(key.digest(), from, build);
  }

  // The same, derived from `values` that an input holds rather than from input ports (the mesh
  // under a canvas, which has no framework key of its own): keyed by the values' identity. The
  // entry keeps them alive, so that no other value takes one's address while it lives; results
  // depend on `build` alone, never on whether an entry was found.
  template <typename Build>
  auto derivedFrom(std::string_view what, const std::vector<ValuePtr>& values, Hash extra,
                   const Build& build) {
    Hasher key = derivedKey<Build>(what, extra);
    key.str("by identity");
    for (const ValuePtr& value : values)
      key.u64(std::uint64_t(reinterpret_cast<std::uintptr_t>(value.get())));
    return derivedUnder(key.digest(), values, build);
  }

  // The framework's key of the value on an input port: equal keys mean equal values (equal values
  // may have different keys). 0 where the port is unconnected.
  Hash inputKeyOf(std::string_view port) const { return inputKey(port); }

  // Publishes `value` on `port` as out() does, and lets this node take it back to build a later
  // result in once the framework has retired it and nothing else holds it (recycle). `note` is
  // what the node will need to know then (what the value was made from), kept with the value; it
  // must not be null. `value` must not point to a const object.
  template <ValueType T, typename Note>
  void outRecyclable(std::string_view port, std::shared_ptr<T> value,
                     std::shared_ptr<const Note> note) {
    if (!note) throw NodeError::output(port, "was published as recyclable with no note");
    out(port, value);
    keepRecyclable(port, {std::move(value), std::move(note), &typeid(Note)});
  }

  // A value this node published on `port` with outRecyclable and a Note that `accepts` (called
  // with a `const Note&`), which the framework has retired and nothing else holds: the node holds
  // it alone and may change it and publish it again. Empty where there is none (as always on a
  // fresh evaluator). It is an allocation strategy: a result never depends on whether one was
  // found.
  template <ValueType T, typename Note, typename Accepts>
  Recycled<T, Note> recycle(std::string_view port, const Accepts& accepts) {
    RecyclableValue taken = recycledValue(port, [&](const RecyclableValue& retired) {
      return retired.noteType && *retired.noteType == typeid(Note) &&
             dynamic_cast<const T*>(retired.value.get()) &&
             accepts(*static_cast<const Note*>(retired.note.get()));
    });
    if (!taken.value) return {};
    return {std::const_pointer_cast<T>(std::static_pointer_cast<const T>(std::move(taken.value))),
            std::static_pointer_cast<const Note>(std::move(taken.note))};
  }

 private:
  template <typename Build>
  using DerivedType =
      std::add_const_t<typename decltype(std::declval<const Build&>()())::element_type>;

  // The start of a derived entry's key: the C++ type, the derivation's name and its params.
  template <typename Build>
  static Hasher derivedKey(std::string_view what, Hash extra) {
    Hasher key;
    key.str(typeid(DerivedType<Build>).name()).str(what).u64(extra);
    return key;
  }

  template <typename Build>
  auto derivedUnder(Hash key, const std::vector<ValuePtr>& from, const Build& build) {
    using T = DerivedType<Build>;
    const auto made = derivedValue(
        key, from, [&]() -> std::shared_ptr<const void> { return std::shared_ptr<T>(build()); });
    return std::static_pointer_cast<T>(made);
  }

 protected:
  virtual ValuePtr inputValue(std::string_view port) const = 0;
  virtual const ParamValue& paramValue(std::string_view name) const = 0;
  // The framework's key of the value on an input port: equal keys mean equal values. 0 where the
  // port is unconnected.
  virtual Hash inputKey(std::string_view port) const = 0;
  virtual std::shared_ptr<const void> derivedValue(
      Hash key, const std::vector<ValuePtr>& derivedFrom,
      const std::function<std::shared_ptr<const void>()>& build) = 0;
  // The framework's side of outRecyclable and recycle; a context without a RecycleBin keeps
  // nothing and finds nothing.
  virtual void keepRecyclable(std::string_view, RecyclableValue) {}
  virtual RecyclableValue recycledValue(std::string_view,
                                        const std::function<bool(const RecyclableValue&)>&) {
    return {};
  }
};

template <typename T>
T Context::param(std::string_view name) const {
  const ParamValue& value = paramValue(name);
  if constexpr (std::is_same_v<T, int>) {
    return static_cast<int>(std::get<std::int64_t>(value));
  } else {
    return std::get<T>(value);
  }
}

// One node instance in a graph. Its outputs depend on its inputs and params alone: after any
// history of computes they equal a fresh instance's, bit for bit. Data derived from inputs
// belongs in Context::derived, not in the node (core/DESIGN.md).
class Node {
 public:
  virtual ~Node() = default;
  // Where the type declares prepareInputs (NodeTypeBuilder::prepares), every computation of the
  // node is prepare() and then compute(), on this instance. prepare() sees those inputs alone and
  // does the part of the work that needs no other: the evaluator runs it on another thread as
  // soon as they are ready, while it computes the node's other inputs. It may not set outputs or
  // write files; its warnings are the node's, and what it throws is the node's failure.
  virtual void prepare(Context&) {}
  virtual void compute(Context& ctx) = 0;
  // For node types outside this repository that warm-start: true when the last compute()
  // started from state left by earlier ones, so that its outputs may differ from a fresh
  // instance's within the node's tolerance. The evaluator recomputes such outputs with a fresh
  // instance when asked to settle.
  virtual bool usedHistory() const { return false; }
};

struct PortDecl {
  std::string name;
  std::string typeId;
  std::string doc;
  bool optional = false;
};

// Rewrites the params of a node saved at version k into version k + 1.
using UpgradeFn = std::function<void(ParamMap& params)>;

struct NodeType {
  std::string id;  // stable, e.g. "geobrush.load_mesh"
  int version = 1;
  std::string label;
  std::string category;
  std::string doc;
  std::vector<PortDecl> inputs;
  std::vector<PortDecl> outputs;
  std::vector<ParamDecl> params;
  std::function<std::unique_ptr<Node>()> create;
  std::vector<std::string> prepareInputs;  // the inputs Node::prepare reads; empty: none
  std::map<int, UpgradeFn> upgrades;       // key: the version upgraded from
  std::string library;                     // filled by the plugin loader

  const PortDecl* findInput(std::string_view name) const;
  const PortDecl* findOutput(std::string_view name) const;
  const ParamDecl* findParam(std::string_view name) const;
  // Whether writing files is part of what it does (the output-path params).
  bool writesFiles() const;
};

// Declares a node type in one chained expression, e.g.
//   NodeTypeBuilder("geobrush.transform", 1)
//       .doc("Moves, rotates and scales a mesh.")
//       .input<Mesh>("mesh", "The mesh to transform.")
//       .output<Mesh>("mesh", "The transformed mesh.")
//       .paramDouble("scale", 1.0, "Uniform scale factor.").range(1e-9, 1e9)
//       .node<TransformNode>()
//       .build();
class NodeTypeBuilder {
 public:
  NodeTypeBuilder(std::string id, int version);

  NodeTypeBuilder& label(std::string text);
  NodeTypeBuilder& category(std::string text);
  NodeTypeBuilder& doc(std::string text);

  template <ValueType T>
  NodeTypeBuilder& input(std::string name, std::string doc) {
    type_.inputs.push_back({std::move(name), std::string(T::kTypeId), std::move(doc), false});
    return *this;
  }
  template <ValueType T>
  NodeTypeBuilder& optionalInput(std::string name, std::string doc) {
    type_.inputs.push_back({std::move(name), std::string(T::kTypeId), std::move(doc), true});
    return *this;
  }
  template <ValueType T>
  NodeTypeBuilder& output(std::string name, std::string doc) {
    type_.outputs.push_back({std::move(name), std::string(T::kTypeId), std::move(doc), false});
    return *this;
  }

  NodeTypeBuilder& paramBool(std::string name, bool value, std::string doc);
  NodeTypeBuilder& paramInt(std::string name, std::int64_t value, std::string doc);
  NodeTypeBuilder& paramDouble(std::string name, double value, std::string doc);
  NodeTypeBuilder& paramString(std::string name, std::string value, std::string doc);
  NodeTypeBuilder& paramEnum(std::string name, std::string value, std::vector<std::string> choices,
                             std::string doc);
  NodeTypeBuilder& paramInputPath(std::string name, std::string doc);
  NodeTypeBuilder& paramOutputPath(std::string name, std::string value, std::string doc);
  NodeTypeBuilder& paramVec3(std::string name, Vec3 value, std::string doc);
  NodeTypeBuilder& paramList(std::string name, int rowSize, std::vector<double> value,
                             std::string doc);
  // Inclusive bounds for the last declared parameter.
  NodeTypeBuilder& range(double min, double max);

  template <typename N>
  NodeTypeBuilder& node() {
    type_.create = [] { return std::make_unique<N>(); };
    return *this;
  }
  // A stateless node given as a function.
  NodeTypeBuilder& compute(std::function<void(Context&)> fn);
  // The declared inputs that the node's prepare() needs (see Node::prepare).
  NodeTypeBuilder& prepares(std::vector<std::string> inputs);
  NodeTypeBuilder& upgrade(int fromVersion, UpgradeFn fn);

  NodeType build() const;

 private:
  NodeTypeBuilder& addParam(ParamDecl decl);
  NodeType type_;
};

}  // namespace geobrush
