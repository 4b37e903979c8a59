// Evaluating from Python: shared by Evaluator.evaluate and clone().
#pragma once

#include <pybind11/pybind11.h>

#include "bindings.hpp"
#include "geobrush/evaluator.hpp"

namespace geobrush::python {

struct PyEvaluator {
  Evaluator evaluator{registry()};
};

struct PyReport {
  EvalReport report;
  CollectedMetrics metrics;
};

PyReport evaluateGraph(PyEvaluator& self, const PyGraph& graph, const py::object& outDir,
                       const py::object& targets, const py::object& progress, bool check);

// Evaluates with the GIL released, calling `progress` (None or a callable(node, fraction)) and
// stopping on Ctrl-C; raises EvaluationError for a failed evaluation when `check`.
PyReport evaluateChecked(Evaluator& evaluator, const Graph& graph, EvalOptions options,
                         const py::object& progress, bool check);

}  // namespace geobrush::python
