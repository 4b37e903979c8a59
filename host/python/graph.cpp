// geobrush.Graph: graph files read, built and edited from Python, checked as the command checks
// them.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "geobrush/text.hpp"

namespace geobrush::python {
namespace {

const NodeType& typeOf(const Graph& graph, const std::string& node) {
  const auto it = graph.nodes.find(node);
  if (it == graph.nodes.end()) throw GraphError(graph.file, node, "", "no node of that name");
  const NodeType* type = registry().find(it->second.type);
  if (!type)
    throw GraphError(graph.file, node, "", "unknown node type " + quoteText(it->second.type));
  return *type;
}

const ParamDecl& declOf(const Graph& graph, const std::string& node, const std::string& param) {
  const NodeType& type = typeOf(graph, node);
  const ParamDecl* decl = type.findParam(param);
  if (!decl)
    throw GraphError(graph.file, node, "param " + quoteText(param),
                     quoteText(type.id) + " declares no such parameter");
  return *decl;
}

// "node.port" split at its last dot (node names may hold dots, port names may not).
Endpoint endpointOf(const Graph& graph, const std::string& text) {
  const auto dot = text.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == text.size())
    throw GraphError(graph.file, "", "", "expected NODE.PORT, got " + quoteText(text));
  return {text.substr(0, dot), text.substr(dot + 1)};
}

// Applies an edit and checks the whole graph; a rejected edit leaves the graph as it was.
template <typename Edit>
void edit(PyGraph& self, const Edit& change) {
  Graph edited = self.graph;
  change(edited);
  prepareGraph(edited, registry(), /*requireInputs=*/false);
  self.graph = std::move(edited);
}

PyGraph loadGraph(const std::filesystem::path& path) {
  PyGraph result{readGraphFile(path)};
  prepareGraph(result.graph, registry());
  return result;
}

void addNode(PyGraph& self, const std::string& name, const std::string& type,
             const py::kwargs& params) {
  edit(self, [&](Graph& graph) {
    if (name.empty() || graph.nodes.contains(name))
      throw GraphError(graph.file, name, "",
                       name.empty() ? "a node needs a name" : "a node of that name exists");
    if (!registry().find(type))
      throw GraphError(
          graph.file, name, "",
          "unknown node type " + quoteText(type) + " (geobrush.node_types() lists them)");
    graph.nodes[name] = GraphNode{type, registry().find(type)->version, {}};
    for (const auto& [key, value] : params) {
      const std::string param = py::str(key);
      graph.nodes[name].params[param] =
          paramFromPython(value, declOf(graph, name, param), graph, name);
    }
  });
}

void removeNode(PyGraph& self, const std::string& name) {
  edit(self, [&](Graph& graph) {
    if (!graph.nodes.erase(name)) throw GraphError(graph.file, name, "", "no node of that name");
    graph.ui.erase(name);
    std::erase_if(graph.connections,
                  [&](const Connection& c) { return c.from.node == name || c.to.node == name; });
  });
}

void connect(PyGraph& self, const std::string& from, const std::string& to) {
  edit(self, [&](Graph& graph) {
    const Endpoint target = endpointOf(graph, to);
    std::erase_if(graph.connections, [&](const Connection& c) { return c.to == target; });
    graph.connections.push_back({endpointOf(graph, from), target});
  });
}

void disconnect(PyGraph& self, const std::string& to) {
  edit(self, [&](Graph& graph) {
    const Endpoint target = endpointOf(graph, to);
    if (!std::erase_if(graph.connections, [&](const Connection& c) { return c.to == target; }))
      throw GraphError(graph.file, target.node, "input " + quoteText(target.port),
                       "is not connected");
  });
}

py::object getParam(const PyGraph& self, const std::string& node, const std::string& param) {
  const ParamDecl& decl = declOf(self.graph, node, param);
  const auto& params = self.graph.nodes.at(node).params;
  const auto it = params.find(param);
  return paramToPython(it == params.end() ? decl.defaultValue : it->second);
}

void setParam(PyGraph& self, const std::string& node, const std::string& param,
              const py::handle& value) {
  setParamFromPython(self.graph, node, param, value);
}

py::dict paramsOf(const PyGraph& self, const std::string& node) {
  py::dict result;
  for (const auto& decl : typeOf(self.graph, node).params)
    result[py::str(decl.name)] = getParam(self, node, decl.name);
  return result;
}

// "node.param" split at its last dot.
std::pair<std::string, std::string> paramKey(const Graph& graph, const std::string& key) {
  const Endpoint endpoint = endpointOf(graph, key);
  return {endpoint.node, endpoint.port};
}

void bindGraphType(py::module_& module) {
  py::class_<PyGraph>(module, "Graph",
                      "A node graph: Graph.load(path) reads a graph file, Graph() starts an empty "
                      "one. Every edit is checked against the node types at once; a rejected edit "
                      "raises GraphError and changes nothing.")
      .def(py::init<>())
      .def_static(
          "load", &loadGraph, py::arg("path"),
          "Reads and checks a graph file. Raises GraphError naming the file, node and port.")
      .def_property_readonly(
          "file",
          [](const PyGraph& self) -> py::object {
            if (self.graph.file.empty()) return py::none();
            return py::str(self.graph.file.string());
          },
          "The file it was read from (relative paths in params resolve against its folder), or "
          "None.")
      .def_property_readonly(
          "nodes",
          [](const PyGraph& self) {
            std::vector<std::string> names;
            for (const auto& [name, node] : self.graph.nodes)
              names.push_back(name);
            return names;
          },
          "Node names, sorted.")
      .def(
          "node_type",
          [](const PyGraph& self, const std::string& node) { return typeOf(self.graph, node).id; },
          py::arg("node"))
      .def_property_readonly(
          "connections",
          [](const PyGraph& self) {
            std::vector<std::pair<std::string, std::string>> result;
            for (const auto& c : self.graph.connections)
              result.emplace_back(c.from.node + "." + c.from.port, c.to.node + "." + c.to.port);
            return result;
          },
          "(\"node.output\", \"node.input\") pairs.")
      .def("add_node", &addNode, py::arg("name"), py::arg("type"),
           "add_node(name, type, **params): a node of a type from geobrush.node_types().")
      .def("remove_node", &removeNode, py::arg("name"), "Removes a node and its connections.")
      .def("connect", &connect, py::arg("output"), py::arg("input"),
           "connect(\"node.output\", \"node.input\"), replacing what fed that input.")
      .def("disconnect", &disconnect, py::arg("input"))
      .def("get", &getParam, py::arg("node"), py::arg("param"),
           "A param's value (its default if unset).")
      .def("set", &setParam, py::arg("node"), py::arg("param"), py::arg("value"),
           "Sets a param, checked against its kind and range. Raises GraphError.")
      .def("params", &paramsOf, py::arg("node"), "Every param of a node with its value.")
      .def("__getitem__",
           [](const PyGraph& self, const std::string& key) {
             const auto [node, param] = paramKey(self.graph, key);
             return getParam(self, node, param);
           })
      .def("__setitem__",
           [](PyGraph& self, const std::string& key, const py::handle& value) {
             const auto [node, param] = paramKey(self.graph, key);
             setParam(self, node, param, value);
           })
      .def(
          "assign",
          [](PyGraph& self, const std::string& assignment) {
            setParamFromText(self.graph, registry(), assignment);
          },
          py::arg("assignment"),
          "Sets NODE.PARAM=VALUE from its text, as `geobrush run --set` does.")
      .def(
          "check", [](PyGraph& self) { prepareGraph(self.graph, registry()); },
          "Checks that the graph can be evaluated (every required input connected).")
      .def(
          "save",
          [](const PyGraph& self, const std::filesystem::path& path) {
            writeGraphFile(self.graph, path, &registry());
          },
          py::arg("path"), "Writes the graph file that `geobrush run` and the studio open.")
      .def("to_json", [](const PyGraph& self) { return serializeGraph(self.graph, &registry()); })
      .def("copy", [](const PyGraph& self) { return PyGraph{self.graph}; })
      .def("__repr__", [](const PyGraph& self) {
        return "<geobrush.Graph " + std::to_string(self.graph.nodes.size()) + " nodes, " +
               std::to_string(self.graph.connections.size()) + " connections>";
      });
}

}  // namespace

ParamValue paramFromPython(const py::handle& value, const ParamDecl& decl, const Graph& graph,
                           const std::string& node) {
  ParamValue loose;
  if (py::isinstance<py::bool_>(value)) {
    loose = value.cast<bool>();
  } else if (py::isinstance<py::int_>(value)) {
    loose = value.cast<std::int64_t>();
  } else if (py::isinstance<py::float_>(value)) {
    loose = value.cast<double>();
  } else if (py::isinstance<py::str>(value)) {
    loose = value.cast<std::string>();
  } else if (py::hasattr(value, "__fspath__")) {
    loose = py::str(value.attr("__fspath__")()).cast<std::string>();
  } else {
    try {
      loose = value.cast<std::vector<double>>();
    } catch (const py::cast_error&) {
      throw GraphError(graph.file, node, "param " + quoteText(decl.name),
                       "cannot use a Python " +
                           std::string(py::str(value.get_type().attr("__name__"))) + " here");
    }
  }
  try {
    return coerceParam(decl, loose);
  } catch (const std::invalid_argument& e) {
    throw GraphError(graph.file, node, "param " + quoteText(decl.name), e.what());
  }
}

void setParamFromPython(Graph& graph, const std::string& node, const std::string& param,
                        const py::handle& value) {
  const ParamDecl& decl = declOf(graph, node, param);
  graph.nodes.at(node).params[param] = paramFromPython(value, decl, graph, node);
}

py::object paramToPython(const ParamValue& value) {
  return std::visit(
      [](const auto& v) -> py::object {
        using T = std::decay_t<decltype(v)>;
        if constexpr (std::is_same_v<T, Vec3>)
          return py::make_tuple(v[0], v[1], v[2]);
        else
          return py::cast(v);
      },
      value);
}

void bindGraph(py::module_& module) {
  bindGraphType(module);
}

}  // namespace geobrush::python
