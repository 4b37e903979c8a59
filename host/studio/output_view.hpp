// The view of a graph without a clone: one node's mesh output in a viewport (orbit, pan and zoom
// as in the clone's views), named above it. It shows the selected node's mesh, or where that
// node has none the graph's result: the last node, in the graph's order, whose mesh output no
// node that makes meshes reads (what is saved, rendered or measured).
#pragma once

#include <QWidget>
#include <optional>
#include <string>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/registry.hpp"
#include "viewport.hpp"

class QLabel;

namespace geobrush::studio {

// The mesh output to show: the selected node's first mesh output with a value, else the graph's
// result as above; none where the evaluator holds no such mesh.
std::optional<Endpoint> meshOutputToShow(const Graph& graph, const NodeRegistry& registry,
                                         const Evaluator& evaluator, const std::string& selected);

class OutputView : public QWidget {
 public:
  explicit OutputView(QWidget* parent = nullptr);

  // Shows the mesh of `output`; framed anew when the output shown changes, kept framed while the
  // same output is shown again (a re-evaluated result does not move the view).
  void showMesh(const Endpoint& output, MeshPtr mesh);
  // Shows nothing, saying how to get a mesh to show.
  void showNothing();
  const std::optional<Endpoint>& shown() const { return shown_; }
  QString caption() const;
  Viewport& viewport() { return *viewport_; }

 private:
  QLabel* caption_;
  Viewport* viewport_;
  std::optional<Endpoint> shown_;
};

}  // namespace geobrush::studio
