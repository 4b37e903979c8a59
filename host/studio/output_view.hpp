// The view of a graph without a clone: one node's mesh output in a viewport (orbit, pan and zoom
// as in the clone's views), or its image, named above it. It shows the selected node's mesh (or
// image, as the render node's), or where that node has neither the graph's result: the last node,
// in the graph's order, whose mesh output no node that makes meshes reads (what is saved, rendered
// or measured). Where the mesh shown is a geobrush.handle_edit's template, a left drag on it is a
// handle edit (Freeform surface inpainting, section 5): the press adds an edit row whose handle is
// the point under the pointer, and the drag moves the handle in the plane facing the view through
// it; the drag is one undoable edit.
#pragma once

#include <QWidget>
#include <functional>
#include <optional>
#include <string>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/registry.hpp"
#include "studio_document.hpp"
#include "viewport.hpp"

class QLabel;

namespace geobrush::studio {

// The output to show: the selected node's first mesh output with a value, else its first image
// output with one, else the graph's result as above; none where the evaluator holds none of them.
std::optional<Endpoint> outputToShow(const Graph& graph, const NodeRegistry& registry,
                                     const Evaluator& evaluator, const std::string& selected);

// A new handle's radius (the graph distance of the vertices it takes along) over the template's
// bounding diagonal.
inline constexpr double kHandleRadiusShare = 0.1;

class OutputView : public QWidget {
 public:
  explicit OutputView(StudioDocument& document, QWidget* parent = nullptr);

  // Shows the mesh of `output`; framed anew when the output shown changes, kept framed while the
  // same output is shown again (a re-evaluated result does not move the view).
  void showMesh(const Endpoint& output, MeshPtr mesh);
  // Shows the image of `output`, fitted to the view.
  void showImage(const Endpoint& output, std::shared_ptr<const Image> image);
  bool showsImage() const;
  // Shows nothing, saying how to get a mesh to show.
  void showNothing();
  const std::optional<Endpoint>& shown() const { return shown_; }
  QString caption() const;
  Viewport& viewport() { return *viewport_; }

  // After each edit of the graph, or with the error of an edit that was refused.
  std::function<void(const std::string& error)> onEdited;

 private:
  void pointer(const PointerEvent& event);
  // The handle edit's translation for the pointer at `position`: in the plane through the handle
  // facing the eye.
  std::optional<Eigen::Vector3d> dragTranslation(const QPointF& position) const;

  StudioDocument& document_;
  QLabel* caption_;
  Viewport* viewport_;
  QLabel* image_;
  std::optional<Endpoint> shown_;
  std::optional<Eigen::Vector3d> handle_;  // where the handle being dragged was picked
};

}  // namespace geobrush::studio
