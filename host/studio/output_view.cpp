#include "output_view.hpp"

#include <QLabel>
#include <QVBoxLayout>
#include <set>

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

OutputView::OutputView(QWidget* parent)
    : QWidget(parent), caption_(new QLabel(this)), viewport_(new Viewport("Output", this)) {
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(caption_);
  layout->addWidget(viewport_, 1);
  showNothing();
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
