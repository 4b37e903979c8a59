// The node editor: the graph's nodes as boxes with their ports (inputs left, outputs right) and
// its connections as curves, placed at the positions of the graph's "ui" block. The wheel zooms. A
// node shows its state after the last evaluation: grey idle, green ok, orange warnings, red error,
// dashed red when no plugin provides its type (its ports then come from its connections).
#pragma once

#include <QGraphicsScene>
#include <QGraphicsView>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include "studio_document.hpp"

namespace geobrush::studio {

class NodeEditor : public QGraphicsView {
 public:
  NodeEditor(const NodeRegistry& registry, QWidget* parent = nullptr);

  // What the user did; the window turns each into a document edit. A drag from an output port
  // dropped on an input port connects them; Delete removes the selected nodes; a moved box
  // reports where it went; a click on a box selects its node (an empty string: none).
  std::function<void(const Endpoint& from, const Endpoint& to)> onConnect;
  std::function<void(const std::vector<std::string>& nodes)> onDelete;
  std::function<void(const std::string& node, double x, double y)> onMoved;
  std::function<void(const std::string& node)> onSelected;
  // Where a port's dot is in view coordinates (for scripted input); null when not shown.
  std::optional<QPoint> portInView(const Endpoint& port, bool input) const;
  // Where a new node goes: the first place in the visible part of the scene, row by row, where
  // its box overlaps none of `graph`'s placed boxes.
  QPointF freeSpot(const Graph& graph) const;

  // Rebuilds the scene from the document's graph and the statuses.
  void show(const StudioDocument& document, const std::map<std::string, NodeStatus>& statuses);
  // The whole graph in view, as small as it takes (the wheel zooms in again); kept framed as the
  // view is resized, until the wheel zooms or a node is focused.
  void frameGraph();
  // Selects a node's box and scrolls to it at a readable size (a failing node); false where the
  // node has no box.
  bool focusNode(const std::string& node);
  std::vector<std::string> selectedNodes() const;
  // Writes the boxes' positions into the graph's "ui" block: those it held, and those of boxes
  // that were moved (an untouched graph saves back as it was read).
  void storePositions(Graph& graph) const;

 protected:
  void mousePressEvent(QMouseEvent* event) override;
  void mouseMoveEvent(QMouseEvent* event) override;
  void mouseReleaseEvent(QMouseEvent* event) override;
  void keyPressEvent(QKeyEvent* event) override;
  // Zooms toward the pointer.
  void wheelEvent(QWheelEvent* event) override;
  void resizeEvent(QResizeEvent* event) override;

 private:
  const NodeRegistry& registry_;
  QGraphicsScene scene_;
  std::map<std::string, QGraphicsItem*> boxes_;
  std::map<std::string, QPointF> placed_;  // where each box was put
  std::map<std::pair<std::string, std::string>, QPointF> inputAt_, outputAt_;
  std::set<std::string> saved_;           // the nodes whose position the graph held
  std::set<std::string> framedNodes_;     // the nodes shown when the view was last framed
  QGraphicsLineItem* pulling_ = nullptr;  // the line drawn while dragging from an output
  Endpoint pulledFrom_;
  bool framed_ = false;  // the view shows the framed graph, not a zoom or a focused node
};

}  // namespace geobrush::studio
