// The source and target viewports of a clone graph and the paper's tools on them (section 3,
// Fig. 3-4): click the source origin, paint the source canvas with a large brush, click the
// target origin, turn and scale the target canvas, paint the region on either canvas (Shift
// subtracts), drag the target canvas across the surface while the region is kept. Every
// stroke or drag is one undoable edit of the graph (clone_edits.hpp); the brush shows at
// corresponding places on both surfaces.
#pragma once

#include <QWidget>
#include <functional>
#include <memory>
#include <optional>

#include "clone_view.hpp"
#include "studio_document.hpp"
#include "viewport.hpp"

class QActionGroup;
class QDoubleSpinBox;
class QToolBar;
class QComboBox;

namespace geobrush::studio {

enum class CloneTool { SourceOrigin, PaintCanvas, TargetOrigin, MoveTarget, PaintRegion };

// What an evaluation gives the viewports, prepared on the evaluating thread.
struct LiveView {
  CloneValues values;
  ShownSurface source;
  ShownSurface target;
  CoordinateLines sourceLines;
  CoordinateLines targetLines;
  std::shared_ptr<const DomainLocator> sourceLocator;
  std::shared_ptr<const DomainLocator> targetLocator;
  std::vector<FieldLayer> fields;  // what the surfaces can be coloured by
  // The shown surfaces' render geometry, built around their views' centres; null where the view
  // already holds it (a source kept from the last view) or the surface cannot be drawn.
  Renderer::Prepared sourceDrawn;
  Renderer::Prepared targetDrawn;
};
using LiveViewPtr = std::shared_ptr<const LiveView>;

// What the next view starts from: the view shown now (its source surface is kept while the
// source mesh, map and strokes stay the same values, as they do while the target is dragged)
// and the frames the viewports draw around.
struct LiveViewBasis {
  LiveViewPtr shown;
  std::optional<RenderFrame> sourceFrame;
  std::optional<RenderFrame> targetFrame;
};

// Reads the roles' values from the evaluator and prepares the surfaces and their render geometry
// (call on the thread that evaluated), so that showing them leaves the UI thread drawing alone.
LiveView makeLiveView(const Evaluator& evaluator, const CloneRoles& roles, const Graph& graph,
                      const NodeRegistry& registry, const LiveViewBasis& basis = {});

class ClonePanel : public QWidget {
  Q_OBJECT

 public:
  explicit ClonePanel(StudioDocument& document, QWidget* parent = nullptr);

  void setRoles(const CloneRoles& roles) { roles_ = roles; }
  const CloneRoles& roles() const { return roles_; }
  void showView(LiveViewPtr view);
  const LiveView& liveView() const { return *view_; }
  // What an evaluation starting now prepares the next view from.
  LiveViewBasis viewBasis() const;
  // Forgets the shown surfaces and the cameras' frames (a new graph was opened).
  void clear();

  // Frames the source view on its canvas and the target view on the paste (on its canvas before
  // anything is pasted), as a clone opens (F); Frame all (Home) shows the whole surfaces.
  void framePaste();

  // What is drawn over the surfaces: the (u, v) lines (L), the origins' axes (A) and the
  // triangles' edges (Wireframe, W); Clean (C) turns the lines and axes off and shows both
  // surfaces plain, to judge the paste.
  void showLines(bool shown);
  void showAxes(bool shown);
  void showClean();

  void setTool(CloneTool tool);
  CloneTool tool() const { return tool_; }
  // In the units of the source mesh, which the shared domain keeps. [ and ] step it and write the
  // new radius beside the pointer, until it moves on.
  void setBrushRadius(double radius);
  double brushRadius() const;
  // Resizing the brush with the pointer (R, as Blender's F): the disc stays where it is shown and
  // its edge follows the pointer (right grows it, left shrinks it), the radius written beside
  // the pointer; a click or R keeps the new radius, Esc restores the old one. False where no
  // brush is shown under the pointer.
  bool beginBrushResize();
  void endBrushResize(bool keep);
  bool resizingBrush() const { return resize_.has_value(); }

  // Colours a viewport's surface by one of the live view's fields (its label), by its canvas (an
  // empty label), or not at all ("Plain"); false where the field does not fit the surface shown.
  bool colourSourceBy(const std::string& label);
  bool colourTargetBy(const std::string& label);

  Viewport& sourceView() { return *source_; }
  Viewport& targetView() { return *target_; }
  // The tool buttons and the brush radius, for the window to place.
  QToolBar* toolBar() { return toolBar_; }

  // After each edit of the graph, or with the error of an edit that was refused.
  std::function<void(const std::string& error)> onEdited;
  // A hint for the status bar (e.g. painting off the canvas).
  std::function<void(const QString& message)> onMessage;

 private:
  void sourcePointer(const PointerEvent& event);
  void targetPointer(const PointerEvent& event);
  // A region dab where the pointer is, on either surface.
  void paintRegionAt(const ShownSurface& surface, const PointerEvent& event);
  void moveTarget(const PointerEvent& event);
  void gesture(const PointerEvent& event);
  void apply(const std::string& error);
  void message(const QString& text);
  // The point of the target surface (not of the pasted detail) under a hit on the shown target.
  std::optional<Eigen::Vector3d> onTargetSurface(const SurfaceHit& hit) const;
  void hover(const std::optional<Eigen::Vector2d>& uv, const std::optional<SurfaceHit>& canvasHit);
  // The brush radius written beside a window position of a view.
  void noteRadius(Viewport& view, const QPointF& at);
  // Where the pointer is, and over which view (none when it left both).
  void trackPointer(Viewport* view, const PointerEvent& event);
  // The events of a view while the brush is resized; true where they were the resize's.
  bool brushResizeEvent(Viewport& view, const PointerEvent& event);
  // The brush's disc as the view shows it, where it shows one.
  std::optional<Outline> brushOutline(const Viewport& view) const;
  void updateOutlines();
  void updateLines();
  // The surfaces shown again with the chosen colours; the choices refilled from the live view.
  void showColours();
  void refillColourChoices(QComboBox* box, const ShownSurface& surface);

  StudioDocument& document_;
  CloneRoles roles_;
  LiveViewPtr view_ = std::make_shared<const LiveView>();
  Viewport* source_;
  Viewport* target_;
  QToolBar* toolBar_;
  QActionGroup* tools_;
  QDoubleSpinBox* radius_;
  QComboBox* sourceColour_;
  QComboBox* targetColour_;
  QAction* linesAction_;
  QAction* axesAction_;
  CloneTool tool_ = CloneTool::PaintRegion;

  // The brush under the pointer: the domain point (region tool), or the source hit (canvas).
  std::optional<Eigen::Vector2d> hoverUv_;
  std::optional<SurfaceHit> hoverCanvas_;
  // The gesture under way: where the last dab went, where the pointer was.
  std::optional<Eigen::Vector2d> lastUv_;
  std::optional<Eigen::Vector3d> lastPoint_;
  QPointF lastPosition_;
  QPointF originOffset_;  // target origin minus the pointer, on the screen, while dragging
  Viewport* pointerView_ = nullptr;
  QPointF pointerPosition_;
  // The resize under way: its view, the screen point the disc's edge is measured from, and the
  // radius and its length on the screen when it began.
  struct BrushResize {
    Viewport* view;
    QPointF centre;
    double startRadius;
    double startPixels;
  };
  std::optional<BrushResize> resize_;
  bool resizeClick_ = false;  // the press that ended a resize: its moves and release are its own
};

}  // namespace geobrush::studio
