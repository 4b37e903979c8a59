#include "output_view.hpp"

#include <QLabel>
#include <QVBoxLayout>
#include <set>

#include "geobrush/mesh.hpp"

namespace geobrush::studio {
namespace {

MeshPtr meshAt(const Evaluator& evaluator, const Endpoint& output) {
  return std::dynamic_pointer_cast<const Mesh>(evaluator.output(output.node, output.port));
}

// The node's first mesh output that holds a value.
std::optional<Endpoint> firstMeshOutput(const Graph& graph, const NodeRegistry& registry,
                                        const Evaluator& evaluator, const std::string& node) {
  const auto it = graph.nodes.find(node);
  if (it == graph.nodes.end()) return std::nullopt;
  const NodeType* type = registry.find(it->second.type);
  if (!type) return std::nullopt;
  for (const PortDecl& port : type->outputs)
    if (port.typeId == Mesh::kTypeId && meshAt(evaluator, {node, port.name}))
      return Endpoint{node, port.name};
  return std::nullopt;
}

}  // namespace

std::optional<Endpoint> meshOutputToShow(const Graph& graph, const NodeRegistry& registry,
                                         const Evaluator& evaluator, const std::string& selected) {
  if (auto output = firstMeshOutput(graph, registry, evaluator, selected)) return output;
  const auto makesMeshes = [&](const std::string& node) {
    const auto it = graph.nodes.find(node);
    const NodeType* type = it == graph.nodes.end() ? nullptr : registry.find(it->second.type);
    if (!type) return false;
    for (const PortDecl& port : type->outputs)
      if (port.typeId == Mesh::kTypeId) return true;
    return false;
  };
  // Outputs that another mesh-making node reads: steps on the way, not the result.
  std::set<std::pair<std::string, std::string>> intermediate;
  for (const Connection& c : graph.connections)
    if (makesMeshes(c.to.node)) intermediate.insert({c.from.node, c.from.port});
  std::optional<Endpoint> result;
  for (const auto& [name, node] : graph.nodes) {
    const auto output = firstMeshOutput(graph, registry, evaluator, name);
    if (output && !intermediate.count({output->node, output->port})) result = output;
  }
  return result;
}

OutputView::OutputView(StudioDocument& document, QWidget* parent)
    : QWidget(parent),
      document_(document),
      caption_(new QLabel(this)),
      viewport_(new Viewport("Output", this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(caption_);
  layout->addWidget(viewport_, 1);
  showNothing();
  viewport_->onPointer = [this](const PointerEvent& event) { pointer(event); };
}

void OutputView::pointer(const PointerEvent& event) {
  if (!shown_) return;
  const auto node = document_.graph().nodes.find(shown_->node);
  if (node == document_.graph().nodes.end() || node->second.type != "geobrush.handle_edit") return;
  const auto edits = document_.param(shown_->node, "edits");
  if (!edits || !std::holds_alternative<std::vector<double>>(*edits)) return;
  std::vector<double> rows = std::get<std::vector<double>>(*edits);
  std::string error;
  if (event.kind == PointerEvent::Press && event.hit) {
    handle_ = event.hit->point;
    const MeshPtr& mesh = viewport_->surface().mesh;
    const double radius = kHandleRadiusShare * boundingDiagonal(mesh->surface);
    const Eigen::Vector3d& p = *handle_;
    document_.beginGesture();
    rows.insert(rows.end(), {p.x(), p.y(), p.z(), radius, 0, 0, 0, 0, 0, 1, 0});
    error = document_.setParam(shown_->node, "edits", rows);
  } else if (event.kind == PointerEvent::Move && handle_ && rows.size() >= 11) {
    const auto t = dragTranslation(event.position);
    if (!t) return;
    std::copy(t->data(), t->data() + 3, rows.end() - 7);
    error = document_.setParam(shown_->node, "edits", rows);
  } else if (event.kind == PointerEvent::Release && handle_) {
    handle_.reset();
    document_.endGesture();
  } else {
    return;
  }
  if (onEdited) onEdited(error);
}

std::optional<Eigen::Vector3d> OutputView::dragTranslation(const QPointF& position) const {
  const auto camera = viewport_->camera();
  if (!camera || !handle_) return std::nullopt;
  const auto [eye, direction] = camera->ray(position.x(), position.y());
  const Eigen::Vector3d facing = (*handle_ - camera->eye).normalized();
  const double along = direction.dot(facing);
  if (!(along > 1e-6)) return std::nullopt;
  return eye + direction * ((*handle_ - eye).dot(facing) / along) - *handle_;
}

void OutputView::showMesh(const Endpoint& output, MeshPtr mesh) {
  const bool another = shown_ != output;
  shown_ = output;
  caption_->setText(QString::fromStdString(output.node + "." + output.port));
  viewport_->setSurface({std::move(mesh), {}});
  if (another) viewport_->frameAll();
}

void OutputView::showNothing() {
  shown_.reset();
  caption_->setText("Evaluate the graph (F5) to see its meshes here.");
  viewport_->setSurface({});
}

QString OutputView::caption() const {
  return caption_->text();
}

}  // namespace geobrush::studio
