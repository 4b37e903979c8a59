// Evaluating from Python: shared by Evaluator.evaluate and clone().
#pragma once

#include <pybind11/pybind11.h>

#include <mutex>

#include "bindings.hpp"
#include "geobrush/evaluator.hpp"

namespace geobrush::python {

// An evaluator shared by Python threads: one evaluation (or output read) at a time. Whoever waits
// for the lock has released the GIL, so that the evaluation holding it can report progress.
struct PyEvaluator {
  Evaluator evaluator{registry()};
  std::mutex mutex;
};

struct PyReport {
  EvalReport report;
  CollectedMetrics metrics;
};

PyReport evaluateGraph(PyEvaluator& self, const PyGraph& graph, const py::object& outDir,
                       const py::object& targets, const py::object& progress, bool check);

// Evaluates with the GIL released, calling `progress` (None or a callable(node, fraction)) and
// stopping on Ctrl-C; raises EvaluationError for a failed evaluation when `check`.
PyReport evaluateChecked(PyEvaluator& evaluator, const Graph& graph, EvalOptions options,
                         const py::object& progress, bool check);

// An output of the evaluator's last evaluation, or null; waits for one under way.
ValuePtr lockedOutput(PyEvaluator& evaluator, const std::string& node, const std::string& port);

}  // namespace geobrush::python
