// The _geobrush extension module: the registry it shares, its errors, and what it lists.
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "geobrush/clone.hpp"
#include "geobrush/mesh_io.hpp"

namespace geobrush::python {
namespace {

struct LoadedRegistry {
  NodeRegistry registry;
  std::vector<std::string> errors;
  LoadedRegistry() { errors = registry.loadPlugins(defaultPluginDirs()).errors; }
};

// Never destroyed: plugin libraries stay loaded until the interpreter exits, as values from
// them may still be referenced from Python then.
LoadedRegistry& loaded() {
  static auto* instance = new LoadedRegistry;
  return *instance;
}

py::dict portsToPython(const std::vector<PortDecl>& ports) {
  py::dict result;
  for (const auto& port : ports)
    result[py::str(port.name)] = py::dict(py::arg("type") = port.typeId, py::arg("doc") = port.doc,
                                          py::arg("optional") = port.optional);
  return result;
}

py::dict nodeTypeToPython(const NodeType& type) {
  py::dict params;
  for (const auto& param : type.params) {
    py::dict entry(py::arg("kind") = std::string(toString(param.kind)),
                   py::arg("default") = paramToPython(param.defaultValue),
                   py::arg("doc") = param.doc);
    if (param.min) entry["min"] = *param.min;
    if (param.max) entry["max"] = *param.max;
    if (!param.choices.empty()) entry["choices"] = param.choices;
    params[py::str(param.name)] = entry;
  }
  return py::dict(py::arg("id") = type.id, py::arg("version") = type.version,
                  py::arg("doc") = type.doc, py::arg("inputs") = portsToPython(type.inputs),
                  py::arg("outputs") = portsToPython(type.outputs), py::arg("params") = params,
                  py::arg("library") = type.library);
}

}  // namespace

const NodeRegistry& registry() {
  return loaded().registry;
}

const std::vector<std::string>& pluginErrors() {
  return loaded().errors;
}

namespace {

// Sets the Python error indicator to a geobrush.errors exception.
void setError(const char* type, const std::string& message, const std::string& file = {},
              const std::string& node = {}, const std::string& where = {},
              const py::object& report = py::none()) {
  const py::object errorType = py::module_::import("geobrush.errors").attr(type);
  const py::object error = errorType(message, file, node, where, report);
  PyErr_SetObject(errorType.ptr(), error.ptr());
}

}  // namespace

void raise(const char* type, const std::string& message, const std::string& file,
           const std::string& node, const std::string& where, py::object report) {
  setError(type, message, file, node, where, report);
  throw py::error_already_set();
}

void bindErrors(py::module_&) {
  py::register_exception_translator([](std::exception_ptr thrown) {
    try {
      std::rethrow_exception(thrown);
    } catch (const GraphError& e) {
      setError("GraphError", e.what(), e.file().string(), e.node(), e.where());
    } catch (const MeshError& e) {
      setError("MeshError", e.what());
    }
  });
}

}  // namespace geobrush::python

PYBIND11_MODULE(_geobrush, module) {
  using namespace geobrush::python;
  module.doc() = "GeoBrush's node graphs, evaluator and meshes (see the geobrush package).";
  module.attr("__version__") = "0.1.0";
  bindErrors(module);
  bindMesh(module);
  bindGraph(module);
  bindEvaluation(module);
  bindClone(module);
  module.def(
      "node_types",
      [] {
        py::list types;
        for (const auto* type : registry().types())
          types.append(nodeTypeToPython(*type));
        return types;
      },
      "Every node type the plugins provide: id, version, doc, inputs, outputs, params.");
  module.def(
      "plugin_errors", [] { return pluginErrors(); },
      "Why plugin libraries were refused while loading them, one line each.");
  module.def(
      "methods",
      [] {
        py::dict result;
        for (const auto& method : geobrush::findMethods(geobrush::defaultMethodDirs()))
          result[py::str(method.name)] = method.file.string();
        return result;
      },
      "The clone methods found, by name: the graph file of each.");
}
