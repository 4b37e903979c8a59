// geobrush.Evaluator: the command's evaluator and cache, its reports and outputs in Python.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <atomic>

#include "bindings.hpp"
#include "evaluation.hpp"
#include "geobrush/image.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"

namespace geobrush::python {
namespace {

// A value of a type Python has no form for: its type and summary.
struct PyValue {
  ValuePtr value;
};

py::object imageToPython(const Image& image) {
  py::array_t<std::uint8_t> array(
      {py::ssize_t(image.height), py::ssize_t(image.width), py::ssize_t(4)});
  std::copy(image.rgba.begin(), image.rgba.end(), array.mutable_data());
  return array;
}

// Fields as {name: array of one float per vertex}, in their order.
py::object fieldsToPython(const VertexFields& fields) {
  py::dict columns;
  for (const auto& [name, values] : fields.columns) {
    py::array_t<double> array(py::ssize_t(values.size()));
    std::copy(values.begin(), values.end(), array.mutable_data());
    columns[py::str(name)] = array;
  }
  return columns;
}

void bindTypes(py::module_& module) {
  py::class_<NodeRun>(module, "NodeRun", "One node of an evaluation.")
      .def_readonly("node", &NodeRun::node)
      .def_readonly("type", &NodeRun::type)
      .def_readonly("seconds", &NodeRun::seconds)
      .def_readonly("cache_hit", &NodeRun::cacheHit)
      .def_readonly("failed", &NodeRun::failed)
      .def_readonly("warnings", &NodeRun::warnings)
      .def("__repr__", [](const NodeRun& run) {
        return "<geobrush.NodeRun " + run.node + (run.cacheHit ? " cached" : " computed") + ">";
      });
  py::class_<PyReport>(module, "Report", "What an evaluation did.")
      .def_property_readonly("ok", [](const PyReport& r) { return r.report.ok; })
      .def_property_readonly("error", [](const PyReport& r) { return r.report.error; })
      .def_property_readonly(
          "runs", [](const PyReport& r) { return r.report.runs; },
          "NodeRun per node, in evaluation order.")
      .def_property_readonly("computed", [](const PyReport& r) { return r.report.computed(); })
      .def_property_readonly("cache_hits", [](const PyReport& r) { return r.report.cacheHits(); })
      .def_property_readonly("files_written",
                             [](const PyReport& r) { return r.report.filesWritten; })
      .def_property_readonly(
          "metrics", [](const PyReport& r) { return r.metrics.values; },
          "Every Metrics output, as {\"node.name\": value}.")
      .def_property_readonly("notes", [](const PyReport& r) { return r.metrics.notes; })
      .def_property_readonly(
          "node_times",
          [](const PyReport& r) {
            std::map<std::string, double> times;
            for (const auto& run : r.report.runs)
              times[run.node] = run.seconds;
            return times;
          },
          "Seconds per node (cache hits take none).")
      .def_property_readonly("warnings",
                             [](const PyReport& r) {
                               std::vector<std::string> all;
                               for (const auto& run : r.report.runs)
                                 for (const auto& w : run.warnings)
                                   all.push_back(run.node + ": " + w);
                               return all;
                             })
      .def("__repr__", [](const PyReport& r) {
        return std::string("<geobrush.Report ") + (r.report.ok ? "ok" : "failed") + ", " +
               std::to_string(r.report.computed()) + " computed, " +
               std::to_string(r.report.cacheHits()) + " cached>";
      });
  py::class_<PyValue>(module, "Value", "A node output of a type Python has no form for.")
      .def_property_readonly("type",
                             [](const PyValue& v) { return std::string(v.value->typeId()); })
      .def_property_readonly("summary", [](const PyValue& v) { return v.value->summary(); })
      .def("__repr__", [](const PyValue& v) {
        return "<geobrush.Value " + std::string(v.value->typeId()) + ": " + v.value->summary() +
               ">";
      });
}

void bindEvaluator(py::module_& module) {
  py::class_<PyEvaluator>(
      module, "Evaluator",
      "Evaluates graphs, keeping every node's outputs: evaluating again after a param change "
      "recomputes only the nodes that depend on it.")
      .def(py::init<>())
      .def("evaluate", &evaluateGraph, py::arg("graph"), py::kw_only(),
           py::arg("out_dir") = py::none(), py::arg("targets") = py::none(),
           py::arg("progress") = py::none(), py::arg("check") = true,
           "Evaluates the graph (only `targets` and what they need, if given), writing output "
           "files under out_dir (default: the graph file's folder). progress(node, fraction) is "
           "called as nodes compute. Raises EvaluationError naming the file, node and port when a "
           "node fails (with check=False, returns the failed Report instead); nothing is written "
           "then.")
      .def(
          "output",
          [](PyEvaluator& self, const std::string& node, const std::string& port) {
            return valueToPython(lockedOutput(self, node, port));
          },
          py::arg("node"), py::arg("port"),
          "An output of the last evaluation: a Mesh, a dict of metrics, a float, a tuple, an "
          "(h, w, 4) uint8 image array, per-vertex fields as a dict of float arrays by name, a "
          "Value, or None.")
      .def_property_readonly(
          "compute_count",
          [](PyEvaluator& self) {
            py::gil_scoped_release unlocked;
            const std::lock_guard lock(self.mutex);
            return self.evaluator.computeCount();
          },
          "Node computations (cache misses) so far.")
      .def("clear_cache", [](PyEvaluator& self) {
        py::gil_scoped_release unlocked;
        const std::lock_guard lock(self.mutex);
        self.evaluator.clearCache();
      });
}

}  // namespace

ValuePtr lockedOutput(PyEvaluator& self, const std::string& node, const std::string& port) {
  py::gil_scoped_release unlocked;
  const std::lock_guard lock(self.mutex);
  return self.evaluator.output(node, port);
}

py::object valueToPython(const ValuePtr& value) {
  if (!value) return py::none();
  if (auto mesh = std::dynamic_pointer_cast<const Mesh>(value)) return py::cast(PyMesh{mesh});
  if (auto metrics = std::dynamic_pointer_cast<const Metrics>(value))
    return py::cast(metrics->values);
  if (auto scalar = std::dynamic_pointer_cast<const Scalar>(value))
    return py::float_(scalar->value);
  if (auto vector = std::dynamic_pointer_cast<const Vector3>(value))
    return py::make_tuple(vector->value[0], vector->value[1], vector->value[2]);
  if (auto image = std::dynamic_pointer_cast<const Image>(value)) return imageToPython(*image);
  if (auto fields = std::dynamic_pointer_cast<const VertexFields>(value))
    return fieldsToPython(*fields);
  return py::cast(PyValue{value});
}

PyReport evaluateGraph(PyEvaluator& self, const PyGraph& graph, const py::object& outDir,
                       const py::object& targets, const py::object& progress, bool check) {
  EvalOptions options;
  if (!outDir.is_none()) options.outputDir = outDir.cast<std::filesystem::path>();
  if (!targets.is_none()) options.targets = targets.cast<std::vector<std::string>>();
  // A graph being built may leave required inputs open; evaluating one is a graph error.
  Graph checked = graph.graph;
  prepareGraph(checked, registry());
  return evaluateChecked(self, checked, options, progress, check);
}

PyReport evaluateChecked(PyEvaluator& evaluator, const Graph& graph, EvalOptions options,
                         const py::object& progress, bool check) {
  if (!options.outputDir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(options.outputDir, ec);
    if (ec)
      raise("GraphError", "'" + options.outputDir.string() +
                              "': cannot create the output folder: " + ec.message());
  }
  // Ctrl-C cancels the evaluation at the next progress report; the callback's own exception
  // cancels it too, and is raised once the evaluation has stopped.
  std::atomic<bool> cancel{false};
  std::optional<py::error_already_set> callbackError;
  options.cancel = &cancel;
  options.progress = [&](const std::string& node, double fraction) {
    py::gil_scoped_acquire locked;
    if (cancel) return;
    try {
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
      if (!progress.is_none()) progress(node, fraction);
    } catch (py::error_already_set& e) {
      callbackError.emplace(std::move(e));
      cancel = true;
    }
  };
  PyReport result;
  {
    py::gil_scoped_release unlocked;
    const std::lock_guard lock(evaluator.mutex);
    result.report = evaluator.evaluator.evaluate(graph, options);
    if (result.report.ok) result.metrics = collectMetrics(graph, registry(), evaluator.evaluator);
  }
  if (callbackError) {
    callbackError->restore();
    throw py::error_already_set();
  }
  if (!result.report.ok && check)
    raise("EvaluationError", result.report.error, graph.file.string(), result.report.errorNode,
          result.report.errorWhere, py::cast(result));
  return result;
}

void bindEvaluation(py::module_& module) {
  bindTypes(module);
  bindEvaluator(module);
}

}  // namespace geobrush::python
