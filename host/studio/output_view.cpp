#include "output_view.hpp"

#include <QImage>
#include <QLabel>
#include <QPixmap>
#include <QVBoxLayout>
#include <algorithm>
#include <set>

#include "geobrush/mesh.hpp"

namespace geobrush::studio {
namespace {

const NodeType* typeOf(const Graph& graph, const NodeRegistry& registry, const std::string& node) {
  const auto it = graph.nodes.find(node);
  return it == graph.nodes.end() ? nullptr : registry.find(it->second.type);
}

// The node's first output of the type that holds a value.
std::optional<Endpoint> firstOutput(const Graph& graph, const NodeRegistry& registry,
                                    const Evaluator& evaluator, const std::string& node,
                                    std::string_view typeId) {
  const NodeType* type = typeOf(graph, registry, node);
  if (!type) return std::nullopt;
  for (const PortDecl& port : type->outputs)
    if (port.typeId == typeId && evaluator.output(node, port.name))
      return Endpoint{node, port.name};
  return std::nullopt;
}

bool makesMeshes(const NodeType* type) {
  return type && std::any_of(type->outputs.begin(), type->outputs.end(),
                             [](const PortDecl& port) { return port.typeId == Mesh::kTypeId; });
}

// A handle edit's row (handle_edit's `edits`): px, py, pz, radius, tx, ty, tz, ax, ay, az, angle.
constexpr std::size_t kEditRowSize = 11, kEditTranslation = 4;

}  // namespace

std::optional<Endpoint> outputToShow(const Graph& graph, const NodeRegistry& registry,
                                     const Evaluator& evaluator, const std::string& selected) {
  if (auto output = firstOutput(graph, registry, evaluator, selected, Mesh::kTypeId)) return output;
  if (auto output = firstOutput(graph, registry, evaluator, selected, Image::kTypeId))
    return output;
  // Outputs that another mesh-making node reads: steps on the way, not the result.
  std::set<std::pair<std::string, std::string>> intermediate;
  for (const Connection& c : graph.connections)
    if (makesMeshes(typeOf(graph, registry, c.to.node)))
      intermediate.insert({c.from.node, c.from.port});
  std::optional<Endpoint> result;
  for (const auto& [name, node] : graph.nodes) {
    const auto output = firstOutput(graph, registry, evaluator, name, Mesh::kTypeId);
    if (output && !intermediate.count({output->node, output->port})) result = output;
  }
  return result;
}

OutputView::OutputView(StudioDocument& document, QWidget* parent)
    : QWidget(parent),
      document_(document),
      caption_(new QLabel(this)),
      viewport_(new Viewport("Output", this)),
      image_(new QLabel(this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(caption_);
  layout->addWidget(viewport_, 1);
  layout->addWidget(image_, 1);
  image_->setAlignment(Qt::AlignCenter);
  image_->setMinimumSize(240, 200);
  image_->hide();
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
  } else if (event.kind == PointerEvent::Move && handle_ && rows.size() >= kEditRowSize) {
    const auto t = dragTranslation(event.position);
    if (!t) return;
    std::copy(t->data(), t->data() + 3, rows.end() - kEditRowSize + kEditTranslation);
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
  image_->hide();
  viewport_->show();
  viewport_->setSurface({std::move(mesh), {}});
  if (another) viewport_->frameAll();
}

void OutputView::showImage(const Endpoint& output, std::shared_ptr<const Image> image) {
  shown_ = output;
  caption_->setText(QString::fromStdString(output.node + "." + output.port));
  const QImage picture(image->rgba.data(), image->width, image->height, 4 * image->width,
                       QImage::Format_RGBA8888);
  const QSize room = viewport_->isVisible() ? viewport_->size() : image_->size();
  image_->setPixmap(
      QPixmap::fromImage(picture.scaled(room, Qt::KeepAspectRatio, Qt::SmoothTransformation)));
  viewport_->hide();
  image_->show();
}

bool OutputView::showsImage() const {
  return !image_->isHidden();
}

void OutputView::showNothing() {
  shown_.reset();
  image_->hide();
  viewport_->show();
  caption_->setText("Evaluate the graph (F5) to see its meshes here.");
  viewport_->setSurface({});
}

QString OutputView::caption() const {
  return caption_->text();
}

}  // namespace geobrush::studio
