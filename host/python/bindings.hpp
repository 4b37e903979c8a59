// The `geobrush` Python module's C++ side (_geobrush): what its binding files share.
#pragma once

#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "geobrush/graph.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/value.hpp"

namespace geobrush::python {

namespace py = pybind11;

// The node types of every plugin in defaultPluginDirs(), loaded once per process.
const NodeRegistry& registry();
// Why plugins were refused while loading them, one line each.
const std::vector<std::string>& pluginErrors();

// A mesh as Python holds it: immutable, shared with the evaluator's cache.
struct PyMesh {
  MeshPtr mesh;
};

// A graph as Python edits it: always prepared against registry() (inputs may be left open while
// it is being built).
struct PyGraph {
  Graph graph;
};

// An exception of the pure-Python module geobrush.errors (Error, GraphError, EvaluationError,
// MeshError), raised with the file, node and port ("where") as attributes; `report` is attached
// when given.
[[noreturn]] void raise(const char* type, const std::string& message, const std::string& file = {},
                        const std::string& node = {}, const std::string& where = {},
                        py::object report = py::none());

// A Python value (bool, int, float, str, path, sequence of numbers) as a param of `decl`'s kind;
// throws GraphError naming the node and param.
ParamValue paramFromPython(const py::handle& value, const ParamDecl& decl, const Graph& graph,
                           const std::string& node);
// Sets NODE.PARAM of a graph from a Python value, checked against its declaration; throws
// GraphError naming the node and param.
void setParamFromPython(Graph& graph, const std::string& node, const std::string& param,
                        const py::handle& value);
py::object paramToPython(const ParamValue& value);

// A value from a node's output as Python sees it: Mesh, dict of metrics, float, tuple, an
// (h, w, 4) uint8 array for an image, or an opaque Value with its type and summary.
py::object valueToPython(const ValuePtr& value);

void bindErrors(py::module_& module);
void bindMesh(py::module_& module);
void bindGraph(py::module_& module);
void bindEvaluation(py::module_& module);
void bindClone(py::module_& module);

}  // namespace geobrush::python
