// geobrush.clone(): `geobrush clone` from Python, with the same arguments and methods.
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include "bindings.hpp"
#include "evaluation.hpp"
#include "geobrush/clone.hpp"
#include "geobrush/text.hpp"

namespace geobrush::python {
namespace {

namespace fs = std::filesystem;

struct CloneResult {
  PyMesh mesh;
  PyReport report;
  PyGraph graph;
  Vec3 sourcePoint{};
  Vec3 targetPoint{};
};

Vec3 pointOf(const py::handle& value, const char* name) {
  std::vector<double> point;
  try {
    point = value.cast<std::vector<double>>();
  } catch (const py::cast_error&) {
  }
  if (point.size() != 3) raise("GraphError", std::string(name) + ": expected a point x, y, z");
  return {point[0], point[1], point[2]};
}

// `sets` as `geobrush clone --set` takes them: "NODE.PARAM=VALUE" texts, or a dict
// {"NODE.PARAM": value} of Python values.
void applySets(Graph& graph, const py::object& sets) {
  if (sets.is_none()) return;
  if (!py::isinstance<py::dict>(sets)) {
    for (const auto& assignment : sets.cast<std::vector<std::string>>())
      setParamFromText(graph, registry(), assignment);
    return;
  }
  for (const auto& [key, value] : sets.cast<py::dict>()) {
    const std::string text = py::str(key);
    const auto dot = text.rfind('.');
    if (dot == std::string::npos)
      throw GraphError(graph.file, text, "", "expected NODE.PARAM, got " + quoteText(text));
    setParamFromPython(graph, text.substr(0, dot), text.substr(dot + 1), value);
  }
}

// The mesh the method saves.
MeshPtr savedMesh(const Graph& graph, PyEvaluator& evaluator) {
  const Connection* saved = graph.source("save_result", "mesh");
  if (!saved) return nullptr;
  return std::dynamic_pointer_cast<const Mesh>(
      lockedOutput(evaluator, saved->from.node, saved->from.port));
}

struct CloneCall {
  CloneRequest request;
  py::object sets, saveGraph, progress, evaluator;
};

CloneResult cloneFromPython(const CloneCall& call) {
  PyEvaluator own;
  PyEvaluator& evaluator = call.evaluator.is_none() ? own : call.evaluator.cast<PyEvaluator&>();

  CloneResult result;
  Graph& graph = result.graph.graph;
  graph = startCloneGraph(call.request, registry());
  EvalOptions loads;
  loads.targets.assign(std::begin(kCloneMeshNodes), std::end(kCloneMeshNodes));
  evaluateChecked(evaluator, graph, loads, call.progress, true);
  const auto source =
      std::dynamic_pointer_cast<const Mesh>(lockedOutput(evaluator, "source_mesh", "mesh"));
  const auto target =
      std::dynamic_pointer_cast<const Mesh>(lockedOutput(evaluator, "target_mesh", "mesh"));
  if (!source || !target) raise("EvaluationError", "the clone method loads no meshes");
  const SnappedSpec snapped = finishCloneGraph(graph, call.request, registry(), *source, *target);
  applySets(graph, call.sets);
  checkOutputPaths(graph, registry(), fs::current_path());
  result.sourcePoint = snapped.spec.sourcePoint;
  result.targetPoint = snapped.spec.targetPoint;

  result.report = evaluateChecked(evaluator, graph, {}, call.progress, true);
  result.mesh.mesh = savedMesh(graph, evaluator);
  if (!call.saveGraph.is_none())
    writeGraphFile(graph, call.saveGraph.cast<fs::path>(), &registry());
  return result;
}

py::tuple tupleOf(const Vec3& p) {
  return py::make_tuple(p[0], p[1], p[2]);
}

}  // namespace

void bindClone(py::module_& module) {
  py::class_<CloneResult>(module, "CloneResult", "What clone() made.")
      .def_property_readonly(
          "mesh", [](const CloneResult& r) { return r.mesh; }, "The result mesh, as written.")
      .def_property_readonly("metrics",
                             [](const CloneResult& r) { return r.report.metrics.values; })
      .def_property_readonly("report", [](const CloneResult& r) { return r.report; })
      .def_property_readonly(
          "graph", [](const CloneResult& r) { return r.graph; },
          "The filled-in method, which Evaluator.evaluate runs again.")
      .def_property_readonly("files_written",
                             [](const CloneResult& r) { return r.report.report.filesWritten; })
      .def_property_readonly(
          "source_point", [](const CloneResult& r) { return tupleOf(r.sourcePoint); },
          "The source point, snapped to the source surface.")
      .def_property_readonly(
          "target_point", [](const CloneResult& r) { return tupleOf(r.targetPoint); },
          "The target point, snapped to the target surface.");
  module.def(
      "clone",
      [](const fs::path& source, const py::object& sourcePoint, double radius,
         const fs::path& target, const py::object& targetPoint, double scale, double angle,
         const std::string& method, const py::object& sets, const py::object& output,
         const py::object& image, const py::object& saveGraph, const py::object& progress,
         const py::object& evaluator) {
        CloneCall call{{}, sets, saveGraph, progress, evaluator};
        CloneSpec& spec = call.request.spec;
        spec = {source, pointOf(sourcePoint, "source_point"), radius,
                target, pointOf(targetPoint, "target_point"), scale,
                angle};
        call.request.method = method;
        call.request.outputs.mesh =
            output.is_none() ? defaultCloneOutput(spec) : output.cast<fs::path>();
        if (!image.is_none()) call.request.outputs.image = image.cast<fs::path>();
        return cloneFromPython(call);
      },
      py::arg("source"), py::arg("source_point"), py::arg("radius"), py::arg("target"),
      py::arg("target_point"), py::kw_only(), py::arg("scale") = 1.0, py::arg("angle") = 0.0,
      py::arg("method") = "geobrush", py::arg("set") = py::none(), py::arg("output") = py::none(),
      py::arg("image") = py::none(), py::arg("save_graph") = py::none(),
      py::arg("progress") = py::none(), py::arg("evaluator") = py::none(),
      "Clones the surface within geodesic `radius` of `source_point` on the `source` mesh onto "
      "`target` at `target_point`, scaled by `scale` and turned by `angle` degrees, as "
      "`geobrush clone` does (same methods, same defaults; `set` takes \"NODE.PARAM=VALUE\" "
      "texts or a {\"NODE.PARAM\": value} dict). Writes `output` (default "
      "SOURCE_on_TARGET.obj here), `image` and `save_graph` when given. Pass an Evaluator to "
      "reuse what earlier clones computed (e.g. the source side when only the target changes). "
      "Raises GraphError for bad arguments and EvaluationError when a node fails; nothing is "
      "written then.");
}

}  // namespace geobrush::python
