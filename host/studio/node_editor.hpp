// The node editor: the graph's nodes as boxes with their ports (inputs left, outputs right) and
// its connections as curves, placed at the positions of the graph's "ui" block. A node shows its
// state after the last evaluation: grey idle, green ok, orange warnings, red error, dashed red
// when no plugin provides its type (its ports then come from its connections).
#pragma once

#include <QGraphicsScene>
#include <QGraphicsView>
#include <map>
#include <set>
#include <string>

#include "studio_document.hpp"

namespace geobrush::studio {

class NodeEditor : public QGraphicsView {
 public:
  NodeEditor(const NodeRegistry& registry, QWidget* parent = nullptr);

  // Rebuilds the scene from the document's graph and the statuses.
  void show(const StudioDocument& document, const std::map<std::string, NodeStatus>& statuses);
  // Writes the boxes' positions into the graph's "ui" block: those it held, and those of boxes
  // that were moved (an untouched graph saves back as it was read).
  void storePositions(Graph& graph) const;

 private:
  const NodeRegistry& registry_;
  QGraphicsScene scene_;
  std::map<std::string, QGraphicsItem*> boxes_;
  std::map<std::string, QPointF> placed_;  // where each box was put
  std::set<std::string> saved_;            // the nodes whose position the graph held
};

}  // namespace geobrush::studio
