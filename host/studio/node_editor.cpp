#include "node_editor.hpp"

#include <QGraphicsLineItem>
#include <QGraphicsPathItem>
#include <QGraphicsRectItem>
#include <QGraphicsSimpleTextItem>
#include <QKeyEvent>
#include <QMouseEvent>
#include <QPainterPath>
#include <QPen>
#include <QResizeEvent>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>
#include <set>

namespace geobrush::studio {

namespace {
// Boxes are read at kMinScale and above; framing a whole graph may go down to kFitScale.
constexpr double kMinScale = 0.7;
constexpr double kFitScale = 0.2;
constexpr double kMaxScale = 3;
}  // namespace
namespace {

constexpr double kWidth = 190;
constexpr double kTitle = 24;
constexpr double kRow = 18;
constexpr double kPort = 5;

// Item data keys: a box holds its node name; a port its node, port and side.
constexpr int kNodeKey = 0;
constexpr int kPortKey = 1;
constexpr int kSideKey = 2;  // "in" or "out"

QColor stateColor(NodeState state) {
  switch (state) {
    case NodeState::Ok:
      return QColor(70, 150, 90);
    case NodeState::Warning:
      return QColor(220, 150, 30);
    case NodeState::Error:
    case NodeState::Missing:
      return QColor(200, 50, 50);
    case NodeState::Idle:
      break;
  }
  return QColor(110, 110, 120);
}

struct Ports {
  std::vector<std::string> inputs, outputs;
};

// The ports of a node: its type's, or for a missing type the ones its connections name.
Ports portsOf(const NodeRegistry& registry, const Graph& graph, const std::string& name) {
  Ports ports;
  if (const NodeType* type = registry.find(graph.nodes.at(name).type)) {
    for (const auto& port : type->inputs)
      ports.inputs.push_back(port.name);
    for (const auto& port : type->outputs)
      ports.outputs.push_back(port.name);
    return ports;
  }
  std::set<std::string> in, out;
  for (const auto& c : graph.connections) {
    if (c.to.node == name) in.insert(c.to.port);
    if (c.from.node == name) out.insert(c.from.port);
  }
  ports.inputs.assign(in.begin(), in.end());
  ports.outputs.assign(out.begin(), out.end());
  return ports;
}

// Where nodes without a saved position go: a column per depth in the graph (sources left), in
// name order down each column.
std::map<std::string, QPointF> layered(const Graph& graph) {
  std::map<std::string, int> depth;
  std::vector<std::string> order;
  try {
    order = topologicalOrder(graph);
  } catch (const GraphError&) {
    for (const auto& [name, node] : graph.nodes)
      order.push_back(name);
  }
  for (const auto& name : order) {
    int d = 0;
    for (const auto& c : graph.connections)
      if (c.to.node == name && depth.count(c.from.node)) d = std::max(d, depth[c.from.node] + 1);
    depth[name] = d;
  }
  std::map<int, int> filled;
  std::map<std::string, QPointF> at;
  for (const auto& [name, node] : graph.nodes) {
    const int d = depth[name];
    at[name] = QPointF(250.0 * d, 130.0 * filled[d]++);
  }
  return at;
}

}  // namespace

NodeEditor::NodeEditor(const NodeRegistry& registry, QWidget* parent)
    : QGraphicsView(parent), registry_(registry) {
  setScene(&scene_);
  setRenderHint(QPainter::Antialiasing);
  setDragMode(QGraphicsView::RubberBandDrag);
  setTransformationAnchor(QGraphicsView::AnchorUnderMouse);
}

void NodeEditor::wheelEvent(QWheelEvent* event) {
  framed_ = false;
  const double steps = event->angleDelta().y() / 120.0;
  const double zoom = std::clamp(transform().m11() * std::pow(1.15, steps), kFitScale, kMaxScale);
  const double by = zoom / transform().m11();
  scale(by, by);
}

void NodeEditor::frameGraph() {
  fitInView(scene_.sceneRect(), Qt::KeepAspectRatio);
  const double scale = std::clamp(transform().m11(), kFitScale, 1.0);
  setTransform(QTransform::fromScale(scale, scale));
  centerOn(scene_.sceneRect().center());
  framed_ = true;
}

void NodeEditor::resizeEvent(QResizeEvent* event) {
  QGraphicsView::resizeEvent(event);
  if (framed_) frameGraph();
}

std::vector<std::string> NodeEditor::selectedNodes() const {
  std::vector<std::string> names;
  for (const QGraphicsItem* item : scene_.selectedItems())
    if (item->data(kNodeKey).isValid())
      names.push_back(item->data(kNodeKey).toString().toStdString());
  return names;
}

bool NodeEditor::focusNode(const std::string& node) {
  const auto box = boxes_.find(node);
  if (box == boxes_.end()) return false;
  scene_.clearSelection();
  box->second->setSelected(true);
  framed_ = false;
  if (transform().m11() < kMinScale) setTransform(QTransform::fromScale(kMinScale, kMinScale));
  centerOn(box->second);
  return true;
}

void NodeEditor::show(const StudioDocument& document,
                      const std::map<std::string, NodeStatus>& statuses) {
  pulling_ = nullptr;
  scene_.clear();
  boxes_.clear();
  placed_.clear();
  saved_.clear();
  const Graph& graph = document.graph();
  auto& inputAt = inputAt_;
  auto& outputAt = outputAt_;
  inputAt.clear();
  outputAt.clear();
  const std::map<std::string, QPointF> automatic = layered(graph);
  for (const auto& [name, node] : graph.nodes) {
    const Ports ports = portsOf(registry_, graph, name);
    const double height =
        kTitle + kRow * double(std::max(ports.inputs.size(), ports.outputs.size())) + 8;
    const auto saved = graph.ui.find(name);
    const QPointF at =
        saved != graph.ui.end() ? QPointF(saved->second.x, saved->second.y) : automatic.at(name);
    const auto found = statuses.find(name);
    const NodeStatus status = found != statuses.end() ? found->second : NodeStatus{};
    auto* box = scene_.addRect(0, 0, kWidth, height);
    box->setPos(at);
    box->setFlags(QGraphicsItem::ItemIsMovable | QGraphicsItem::ItemIsSelectable);
    QPen pen(stateColor(status.state), status.state == NodeState::Idle ? 1.5 : 3);
    if (status.state == NodeState::Missing) pen.setStyle(Qt::DashLine);
    box->setPen(pen);
    box->setBrush(QColor(245, 245, 248));
    std::string tip = node.type;
    if (!status.message.empty()) tip += "\n" + status.message;
    box->setToolTip(QString::fromStdString(tip));
    auto* title = new QGraphicsSimpleTextItem(QString::fromStdString(name), box);
    title->setPos(6, 4);
    auto* type = new QGraphicsSimpleTextItem(
        QString::fromStdString(status.state == NodeState::Missing ? "missing: " + node.type
                                                                  : node.type),
        box);
    type->setScale(0.75);
    type->setPos(6 + title->boundingRect().width() + 6, 6);
    for (std::size_t i = 0; i < ports.inputs.size(); ++i) {
      const QPointF p(0, kTitle + kRow * (double(i) + 0.5));
      auto* dot = scene_.addEllipse(-kPort, p.y() - kPort, 2 * kPort, 2 * kPort, QPen(Qt::black),
                                    QBrush(QColor(90, 140, 220)));
      dot->setParentItem(box);
      dot->setData(kNodeKey, QString::fromStdString(name));
      dot->setData(kPortKey, QString::fromStdString(ports.inputs[i]));
      dot->setData(kSideKey, "in");
      auto* label = new QGraphicsSimpleTextItem(QString::fromStdString(ports.inputs[i]), box);
      label->setScale(0.8);
      label->setPos(8, p.y() - 7);
      inputAt[{name, ports.inputs[i]}] = at + p;
    }
    for (std::size_t i = 0; i < ports.outputs.size(); ++i) {
      const QPointF p(kWidth, kTitle + kRow * (double(i) + 0.5));
      auto* dot = scene_.addEllipse(kWidth - kPort, p.y() - kPort, 2 * kPort, 2 * kPort,
                                    QPen(Qt::black), QBrush(QColor(230, 170, 60)));
      dot->setParentItem(box);
      dot->setData(kNodeKey, QString::fromStdString(name));
      dot->setData(kPortKey, QString::fromStdString(ports.outputs[i]));
      dot->setData(kSideKey, "out");
      auto* label = new QGraphicsSimpleTextItem(QString::fromStdString(ports.outputs[i]), box);
      label->setScale(0.8);
      label->setPos(kWidth - 8 - 0.8 * label->boundingRect().width(), p.y() - 7);
      outputAt[{name, ports.outputs[i]}] = at + p;
    }
    box->setData(kNodeKey, QString::fromStdString(name));
    boxes_[name] = box;
    placed_[name] = at;
    if (saved != graph.ui.end()) saved_.insert(name);
  }
  for (const auto& c : graph.connections) {
    const auto from = outputAt.find({c.from.node, c.from.port});
    const auto to = inputAt.find({c.to.node, c.to.port});
    if (from == outputAt.end() || to == inputAt.end()) continue;
    QPainterPath path(from->second);
    const double bend = std::max(40.0, std::abs(to->second.x() - from->second.x()) / 2);
    path.cubicTo(from->second + QPointF(bend, 0), to->second - QPointF(bend, 0), to->second);
    auto* curve = scene_.addPath(path, QPen(QColor(60, 60, 70), 1.5));
    curve->setZValue(-1);
  }
  scene_.setSceneRect(scene_.itemsBoundingRect().adjusted(-40, -40, 40, 40));
  // Framed again only when other nodes show (a param edit on every brush dab keeps the view).
  std::set<std::string> names;
  for (const auto& [name, box] : boxes_)
    names.insert(name);
  if (names != framedNodes_) {
    framedNodes_ = std::move(names);
    frameGraph();
  }
}

void NodeEditor::storePositions(Graph& graph) const {
  for (const auto& [name, box] : boxes_)
    if (saved_.count(name) || box->pos() != placed_.at(name))
      graph.ui[name] = {box->pos().x(), box->pos().y()};
}

namespace {

// The port under a scene position, if any.
QGraphicsItem* portAt(const QGraphicsScene& scene, QPointF at) {
  for (QGraphicsItem* item : scene.items(at))
    if (item->data(kSideKey).isValid()) return item;
  return nullptr;
}

Endpoint endpointOf(const QGraphicsItem* port) {
  return {port->data(kNodeKey).toString().toStdString(),
          port->data(kPortKey).toString().toStdString()};
}

}  // namespace

void NodeEditor::mousePressEvent(QMouseEvent* event) {
  const QPointF at = mapToScene(event->pos());
  if (const QGraphicsItem* port = portAt(scene_, at);
      port && event->button() == Qt::LeftButton && port->data(kSideKey).toString() == "out") {
    pulledFrom_ = endpointOf(port);
    pulling_ = scene_.addLine(QLineF(at, at), QPen(QColor(60, 60, 70), 1.5, Qt::DashLine));
    return;
  }
  QGraphicsView::mousePressEvent(event);
  if (onSelected) {
    const auto selected = scene_.selectedItems();
    onSelected(selected.isEmpty() ? std::string()
                                  : selected.front()->data(kNodeKey).toString().toStdString());
  }
}

void NodeEditor::mouseMoveEvent(QMouseEvent* event) {
  if (pulling_) {
    pulling_->setLine(QLineF(pulling_->line().p1(), mapToScene(event->pos())));
    return;
  }
  QGraphicsView::mouseMoveEvent(event);
}

void NodeEditor::mouseReleaseEvent(QMouseEvent* event) {
  if (pulling_) {
    const QGraphicsItem* port = portAt(scene_, mapToScene(event->pos()));
    delete pulling_;
    pulling_ = nullptr;
    if (port && port->data(kSideKey).toString() == "in" && onConnect)
      onConnect(pulledFrom_, endpointOf(port));
    return;
  }
  QGraphicsView::mouseReleaseEvent(event);
  if (!onMoved) return;
  for (const auto& [name, box] : boxes_)
    if (box->pos() != placed_.at(name)) {
      placed_[name] = box->pos();
      onMoved(name, box->pos().x(), box->pos().y());
    }
}

void NodeEditor::keyPressEvent(QKeyEvent* event) {
  if ((event->key() == Qt::Key_Delete || event->key() == Qt::Key_Backspace) && onDelete) {
    std::vector<std::string> names;
    for (const QGraphicsItem* item : scene_.selectedItems())
      if (item->data(kNodeKey).isValid())
        names.push_back(item->data(kNodeKey).toString().toStdString());
    if (!names.empty()) onDelete(names);
    return;
  }
  QGraphicsView::keyPressEvent(event);
}

QPointF NodeEditor::freeSpot(const Graph& graph) const {
  // A cell holds a box (kWidth wide, a few ports tall) and the room for curves around it.
  constexpr double kCellWidth = kWidth + 50, kCellHeight = 140;
  const QRectF visible = mapToScene(viewport()->rect()).boundingRect();
  const int columns = std::max(1, int((visible.width() - 20) / kCellWidth));
  auto taken = [&](const QPointF& at) {
    for (const auto& [name, position] : graph.ui)
      if (std::abs(position.x - at.x()) < kCellWidth && std::abs(position.y - at.y()) < kCellHeight)
        return true;
    return false;
  };
  for (int cell = 0;; ++cell) {
    const QPointF at(visible.left() + 20 + (cell % columns) * kCellWidth,
                     visible.top() + 20 + (cell / columns) * kCellHeight);
    if (!taken(at)) return at;
  }
}

std::optional<QPoint> NodeEditor::portInView(const Endpoint& port, bool input) const {
  const auto& at = input ? inputAt_ : outputAt_;
  const auto it = at.find({port.node, port.port});
  if (it == at.end()) return std::nullopt;
  return mapFromScene(it->second);
}

}  // namespace geobrush::studio
