#include "clone_panel.hpp"

#include <Eigen/Geometry>
#include <QAction>
#include <QActionGroup>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QLabel>
#include <QLineF>
#include <QSignalBlocker>
#include <QSplitter>
#include <QToolBar>
#include <QVBoxLayout>
#include <algorithm>
#include <cmath>
#include <utility>

#include "clone_edits.hpp"

namespace geobrush::studio {
namespace {

// The colour choice that shows a surface without its canvas's colours.
const QString kPlain = "Plain";

// What [ and ] divide and multiply the brush radius by.
constexpr double kBrushStep = 1.25;

// The radius box: its arrows scale the radius as [ and ] do, whatever the mesh's scale.
class RadiusBox : public QDoubleSpinBox {
 public:
  using QDoubleSpinBox::QDoubleSpinBox;
  void stepBy(int steps) override { setValue(value() * std::pow(kBrushStep, steps)); }
};

// Dabs closer than this fraction of the radius to the previous one add nothing a user sees.
constexpr double kDabSpacing = 0.3;
constexpr double kDegreesPerPixel = 0.5;
constexpr double kScalePerPixel = 0.01;

// A brush radius as the status bar and the view write it.
QString radiusText(double radius) {
  return QString::number(radius, 'g', 4);
}

const QColor kBrush(255, 170, 60);
const QColor kEraser(120, 200, 255);
const QColor kUAxis(230, 60, 40);
const QColor kVAxis(60, 110, 240);
const QColor kULine(200, 50, 40, 210);
const QColor kVLine(40, 80, 210, 210);

std::vector<Outline> originMarker(const Frame& frame, double length) {
  return {{{frame.point, frame.point + length * frame.uAxis}, kUAxis, 3},
          {{frame.point, frame.point + length * frame.vAxis}, kVAxis, 3}};
}

// A circle in the plane of the face hit.
Outline tangentCircle(const SurfaceHit& hit, double radius, const QColor& color) {
  Eigen::Vector3d a = hit.normal.unitOrthogonal();
  const Eigen::Vector3d b = hit.normal.cross(a);
  Outline outline{{}, color, 2};
  for (int i = 0; i <= 48; ++i) {
    const double angle = 2 * M_PI * i / 48;
    outline.points.push_back(hit.point + radius * (std::cos(angle) * a + std::sin(angle) * b) +
                             1e-3 * radius * hit.normal);
  }
  return outline;
}

// The box of the shown surface's vertices that `picked` takes; empty where it takes none.
template <typename Pick>
Eigen::AlignedBox3d boxOf(const ShownSurface& surface, Pick picked) {
  Eigen::AlignedBox3d box;
  if (!surface.mesh || surface.uv.size() != surface.mesh->surface.n_vertices()) return box;
  for (auto v : surface.mesh->surface.vertices())
    if (picked(v.idx())) box.extend(pointOf(surface.mesh->surface, v));
  return box;
}

// Whether the source surface, its lines and locator are those of `shown`: they depend on the
// source mesh, its map (the line spacing too) and the strokes' dabs alone (the ROI correction
// gives new strokes, often the same dabs, on every move of the target).
bool sameSource(const LiveView& shown, const CloneValues& values) {
  const auto dabs = [](const StrokesPtr& strokes) { return strokes ? &strokes->dabs : nullptr; };
  const bool sameStrokes = shown.values.strokes == values.strokes ||
                           (dabs(shown.values.strokes) && dabs(values.strokes) &&
                            *dabs(shown.values.strokes) == *dabs(values.strokes));
  return shown.source.mesh && shown.values.sourceMesh == values.sourceMesh &&
         shown.values.sourceMap == values.sourceMap && sameStrokes;
}

}  // namespace

LiveView makeLiveView(const Evaluator& evaluator, const CloneRoles& roles, const Graph& graph,
                      const NodeRegistry& registry, const LiveViewBasis& basis) {
  LiveView view;
  view.fields = fieldLayers(graph, registry, evaluator);
  view.values = fetchClone(evaluator, roles);
  const double spacing = lineSpacing(view.values);
  if (basis.shown && sameSource(*basis.shown, view.values)) {
    view.source = basis.shown->source;
    view.sourceLines = basis.shown->sourceLines;
    view.sourceLocator = basis.shown->sourceLocator;
  } else {
    view.source = showSource(view.values);
    view.sourceLines = coordinateLines(view.source, spacing);
    if (view.values.sourceMap)
      view.sourceLocator = std::make_shared<const DomainLocator>(*view.values.sourceMap);
    if (view.source.mesh)
      view.sourceDrawn = Renderer::prepare({view.source.mesh}, basis.sourceFrame);
  }
  view.target = showTarget(view.values);
  view.targetLines = coordinateLines(view.target, spacing);
  if (view.values.targetMap)
    view.targetLocator = std::make_shared<const DomainLocator>(*view.values.targetMap);
  if (view.target.mesh) view.targetDrawn = Renderer::prepare({view.target.mesh}, basis.targetFrame);
  return view;
}

ClonePanel::ClonePanel(StudioDocument& document, QWidget* parent)
    : QWidget(parent),
      document_(document),
      source_(new Viewport("Source", this)),
      target_(new Viewport("Target", this)),
      toolBar_(new QToolBar("Brush", this)),
      tools_(new QActionGroup(this)),
      radius_(new RadiusBox(this)),
      sourceColour_(new QComboBox(this)),
      targetColour_(new QComboBox(this)) {
  auto* splitter = new QSplitter(Qt::Horizontal, this);
  splitter->addWidget(source_);
  splitter->addWidget(target_);
  auto* layout = new QVBoxLayout(this);
  layout->setContentsMargins(0, 0, 0, 0);
  layout->addWidget(splitter);

  toolBar_->setObjectName("brushToolBar");
  const std::pair<CloneTool, const char*> tools[] = {{CloneTool::SourceOrigin, "Source origin"},
                                                     {CloneTool::PaintCanvas, "Paint canvas"},
                                                     {CloneTool::TargetOrigin, "Target origin"},
                                                     {CloneTool::MoveTarget, "Move target"},
                                                     {CloneTool::PaintRegion, "Paint region"}};
  const char* tips[] = {
      "Click the source surface where the canvas grows from",
      "Paint the source canvas (Shift erases dabs)",
      "Click the target surface where the clone goes",
      "Drag the target canvas across the surface; Shift+drag turns it, Ctrl+drag scales it",
      "Paint the region to clone on either canvas (Shift subtracts)"};
  int key = Qt::Key_1;
  for (std::size_t i = 0; i < std::size(tools); ++i) {
    QAction* action = toolBar_->addAction(tools[i].second);
    action->setCheckable(true);
    action->setToolTip(QString(tips[i]) + " (" + QString::number(i + 1) + ")");
    action->setShortcut(QKeySequence(key++));
    action->setData(int(tools[i].first));
    tools_->addAction(action);
    connect(action, &QAction::triggered, this, [this, tool = tools[i].first] { setTool(tool); });
  }
  toolBar_->addSeparator();
  toolBar_->addWidget(new QLabel(" Brush radius ", this));
  radius_->setObjectName("brushRadius");
  radius_->setDecimals(4);
  radius_->setRange(1e-4, 1e4);
  radius_->setValue(0.1);
  radius_->setToolTip(
      "In source mesh units: the shared domain keeps the source's distances ([ shrinks, ] "
      "grows, R resizes it with the pointer)");
  toolBar_->addWidget(radius_);
  const std::pair<const char*, double> resizes[] = {{"Smaller brush", 1 / kBrushStep},
                                                    {"Larger brush", kBrushStep}};
  for (const auto& [name, factor] : resizes) {
    auto* action = new QAction(name, this);
    action->setShortcut(QKeySequence(factor < 1 ? Qt::Key_BracketLeft : Qt::Key_BracketRight));
    connect(action, &QAction::triggered, this, [this, factor = factor] {
      setBrushRadius(brushRadius() * factor);
      // Written beside the pointer too, until it moves on.
      if (pointerView_ && !resize_) noteRadius(*pointerView_, pointerPosition_);
    });
    addAction(action);
  }
  auto* resize = new QAction("Resize brush", this);
  resize->setShortcut(QKeySequence(Qt::Key_R));
  connect(resize, &QAction::triggered, this, [this] {
    if (resize_)
      endBrushResize(true);
    else if (!beginBrushResize())
      message("Point at a surface with the brush to resize it (R)");
  });
  addAction(resize);
  auto* cancelResize = new QAction("Cancel brush resize", this);
  cancelResize->setShortcut(QKeySequence(Qt::Key_Escape));
  connect(cancelResize, &QAction::triggered, this, [this] { endBrushResize(false); });
  addAction(cancelResize);
  connect(radius_, &QDoubleSpinBox::valueChanged, this, [this](double radius) {
    message("Brush radius " + radiusText(radius));
    updateOutlines();
  });
  toolBar_->addSeparator();
  QAction* framePasteAction = toolBar_->addAction("Frame paste", this, [this] { framePaste(); });
  framePasteAction->setShortcut(QKeySequence(Qt::Key_F));
  framePasteAction->setToolTip("Frame the source canvas and the paste (F)");
  QAction* frameAllAction = toolBar_->addAction("Frame all", this, [this] {
    source_->frameAll();
    target_->frameAll();
  });
  frameAllAction->setShortcut(QKeySequence(Qt::Key_Home));
  frameAllAction->setToolTip("Frame both whole surfaces (Home)");
  toolBar_->addSeparator();
  const auto toggle = [this](const char* name, Qt::Key key, bool on, const char* tip, auto show) {
    QAction* action = toolBar_->addAction(name);
    action->setCheckable(true);
    action->setChecked(on);
    action->setShortcut(QKeySequence(key));
    action->setToolTip(tip);
    connect(action, &QAction::toggled, this, show);
    return action;
  };
  linesAction_ = toggle("Lines", Qt::Key_L, true, "Draw the canvases' (u, v) lines (L)",
                        [this](bool shown) { showLines(shown); });
  axesAction_ = toggle("Axes", Qt::Key_A, true, "Draw the canvases' origins and axes (A)",
                       [this](bool shown) { showAxes(shown); });
  toggle("Wireframe", Qt::Key_W, false, "Draw the triangles' edges over the shading (W)",
         [this](bool shown) {
           source_->setWireframe(shown);
           target_->setWireframe(shown);
         });
  QAction* clean = toolBar_->addAction("Clean", this, [this] { showClean(); });
  clean->setShortcut(QKeySequence(Qt::Key_C));
  clean->setToolTip("No lines, axes or canvas colours: the surfaces as they are (C)");
  toolBar_->addSeparator();
  const std::pair<QComboBox*, const char*> colours[] = {{sourceColour_, " Source colour "},
                                                        {targetColour_, " Target colour "}};
  for (const auto& [box, label] : colours) {
    box->setObjectName(box == sourceColour_ ? "sourceColour" : "targetColour");
    box->setToolTip(
        "Colour the surface by its canvas or by a per-vertex field the graph computed "
        "(emd_signal's, emd's: blue below zero, red above)");
    box->setSizeAdjustPolicy(QComboBox::AdjustToContents);
    box->addItem("Canvas");
    toolBar_->addWidget(new QLabel(label, this));
    toolBar_->addWidget(box);
    connect(box, &QComboBox::currentIndexChanged, this, [this] { showColours(); });
  }
  setTool(tool_);

  source_->onPointer = [this](const PointerEvent& event) { sourcePointer(event); };
  target_->onPointer = [this](const PointerEvent& event) { targetPointer(event); };
}

void ClonePanel::setTool(CloneTool tool) {
  tool_ = tool;
  for (QAction* action : tools_->actions())
    action->setChecked(action->data().toInt() == int(tool));
  hoverUv_.reset();
  hoverCanvas_.reset();
  updateOutlines();
}

void ClonePanel::setBrushRadius(double radius) {
  radius_->setValue(radius);
}

double ClonePanel::brushRadius() const {
  return radius_->value();
}

LiveViewBasis ClonePanel::viewBasis() const {
  return {view_, source_->frame(), target_->frame()};
}

void ClonePanel::clear() {
  source_->setLines({});
  target_->setLines({});
  view_ = std::make_shared<const LiveView>();
  refillColourChoices(sourceColour_, view_->source);
  refillColourChoices(targetColour_, view_->target);
  source_->setSurface({});
  target_->setSurface({});
  source_->setLegend(std::nullopt);
  target_->setLegend(std::nullopt);
  source_->resetView();
  target_->resetView();
  updateOutlines();
}

void ClonePanel::framePaste() {
  const auto onCanvas = [](const ShownSurface& surface) {
    return [&surface](int v) { return surface.uv[std::size_t(v)].allFinite(); };
  };
  source_->frameBox(boxOf(view_->source, onCanvas(view_->source)));
  const ShownSurface& target = view_->target;
  const PasteMapPtr& paste = view_->values.pasteMap;
  const bool pasted = target.mesh && paste &&
                      paste->sourceVertex.size() == target.mesh->surface.n_vertices() &&
                      std::any_of(paste->sourceVertex.begin(), paste->sourceVertex.end(),
                                  [](int v) { return v >= 0; });
  if (pasted)
    target_->frameBox(
        boxOf(target, [&](int v) { return paste->sourceVertex[std::size_t(v)] >= 0; }));
  else
    target_->frameBox(boxOf(target, onCanvas(target)));
}

void ClonePanel::showView(LiveViewPtr view) {
  const bool first = !view_->source.mesh && !view_->target.mesh;
  // The views draw the shown view's lines by pointer: the old one lives until they are replaced.
  const LiveViewPtr previous = std::exchange(view_, std::move(view));
  refillColourChoices(sourceColour_, view_->source);
  refillColourChoices(targetColour_, view_->target);
  showColours();
  updateLines();
  // A clone opens framed on what it copies and where it goes, not on the whole meshes.
  if (first) framePaste();
  updateOutlines();
}

void ClonePanel::showLines(bool shown) {
  linesAction_->setChecked(shown);
  updateLines();
}

void ClonePanel::showAxes(bool shown) {
  axesAction_->setChecked(shown);
  updateOutlines();
}

void ClonePanel::showClean() {
  showLines(false);
  showAxes(false);
  colourSourceBy(kPlain.toStdString());
  colourTargetBy(kPlain.toStdString());
}

void ClonePanel::updateLines() {
  if (!linesAction_->isChecked()) {
    source_->setLines({});
    target_->setLines({});
    return;
  }
  source_->setLines({{&view_->sourceLines.u, kULine}, {&view_->sourceLines.v, kVLine}});
  target_->setLines({{&view_->targetLines.u, kULine}, {&view_->targetLines.v, kVLine}});
}

void ClonePanel::refillColourChoices(QComboBox* box, const ShownSurface& surface) {
  const QSignalBlocker quiet(box);
  const QString chosen = box->currentText();
  box->clear();
  box->addItem("Canvas");
  box->addItem(kPlain);
  const std::size_t count = surface.mesh ? surface.mesh->surface.n_vertices() : 0;
  for (const FieldLayer& layer : view_->fields)
    if (layer.fields->vertexCount == count) box->addItem(QString::fromStdString(layer.label()));
  box->setCurrentIndex(std::max(box->findText(chosen), 0));
}

void ClonePanel::showColours() {
  const auto show = [this](Viewport* view, const ShownSurface& surface,
                           const Renderer::Prepared& drawn, const QComboBox* box,
                           const MeshPtr& plain) {
    if (box->currentText() == kPlain && plain) {
      view->setSurface({plain, surface.uv});
      view->setLegend(std::nullopt);
      return;
    }
    const std::string label = box->currentIndex() > 1 ? box->currentText().toStdString() : "";
    for (const FieldLayer& layer : view_->fields) {
      if (label.empty() || layer.label() != label) continue;
      FieldRange range;
      if (auto coloured = colouredBy(surface, layer, &range)) {
        view->setSurface(*coloured);
        view->setLegend(Legend{layer.column, range});
        return;
      }
    }
    view->setSurface(surface, drawn);
    view->setLegend(std::nullopt);
  };
  const CloneValues& values = view_->values;
  show(source_, view_->source, view_->sourceDrawn, sourceColour_, values.sourceMesh);
  show(target_, view_->target, view_->targetDrawn, targetColour_,
       values.result ? values.result : values.targetMesh);
}

bool ClonePanel::colourSourceBy(const std::string& label) {
  const int index = label.empty() ? 0 : sourceColour_->findText(QString::fromStdString(label));
  if (index < 0) return false;
  sourceColour_->setCurrentIndex(index);
  showColours();
  return true;
}

bool ClonePanel::colourTargetBy(const std::string& label) {
  const int index = label.empty() ? 0 : targetColour_->findText(QString::fromStdString(label));
  if (index < 0) return false;
  targetColour_->setCurrentIndex(index);
  showColours();
  return true;
}

void ClonePanel::message(const QString& text) {
  if (onMessage) onMessage(text);
}

void ClonePanel::apply(const std::string& error) {
  if (onEdited) onEdited(error);
}

void ClonePanel::noteRadius(Viewport& view, const QPointF& at) {
  view.setNote(Viewport::Note{at, "Radius " + radiusText(brushRadius())});
}

void ClonePanel::trackPointer(Viewport* view, const PointerEvent& event) {
  // A radius written by [ or ] goes once the pointer moves on.
  if (!resize_ && view->note()) view->setNote(std::nullopt);
  pointerView_ = event.kind == PointerEvent::Leave ? nullptr : view;
  pointerPosition_ = event.position;
}

bool ClonePanel::brushResizeEvent(Viewport& view, const PointerEvent& event) {
  if (resizeClick_) {
    resizeClick_ = event.kind != PointerEvent::Release;
    return true;
  }
  if (!resize_) return false;
  if (event.kind == PointerEvent::Press) {
    endBrushResize(true);
    resizeClick_ = true;
  } else if (&view == resize_->view && event.kind != PointerEvent::Leave) {
    const double pixels = std::max(QLineF(resize_->centre, event.position).length(), 1.0);
    setBrushRadius(resize_->startRadius * pixels / resize_->startPixels);
    noteRadius(view, event.position);
  }
  return true;
}

bool ClonePanel::beginBrushResize() {
  if (resize_ || !pointerView_) return false;
  const auto outline = brushOutline(*pointerView_);
  const auto camera = pointerView_->camera();
  if (!outline || !camera) return false;
  // The disc's radius on the screen: its outline's mean distance from the pointer, its centre.
  double sum = 0;
  int count = 0;
  for (const Eigen::Vector3d& point : outline->points) {
    const auto at = point.allFinite() ? camera->project(point) : std::nullopt;
    if (!at) continue;
    sum += QLineF(pointerPosition_, QPointF(at->x(), at->y())).length();
    ++count;
  }
  if (count == 0 || !(sum / count >= 1)) return false;
  const double pixels = sum / count;
  // Measured from a point one radius to the left: the pointer starts on the disc's edge.
  resize_ = BrushResize{pointerView_, pointerPosition_ - QPointF(pixels, 0), brushRadius(), pixels};
  noteRadius(*pointerView_, pointerPosition_);
  message("Resizing the brush: move the pointer, click or R keeps the radius, Esc restores it");
  return true;
}

void ClonePanel::endBrushResize(bool keep) {
  if (!resize_) return;
  const BrushResize ended = *resize_;
  resize_.reset();
  ended.view->setNote(std::nullopt);
  if (!keep) setBrushRadius(ended.startRadius);
  message("Brush radius " + radiusText(brushRadius()));
}

void ClonePanel::sourcePointer(const PointerEvent& event) {
  trackPointer(source_, event);
  if (brushResizeEvent(*source_, event)) return;
  if (event.kind == PointerEvent::Leave) return hover(std::nullopt, std::nullopt);
  if (event.kind == PointerEvent::Hover) {
    if (tool_ == CloneTool::PaintCanvas) return hover(std::nullopt, event.hit);
    if (tool_ == CloneTool::PaintRegion && event.hit)
      return hover(uvAt(view_->source, *event.hit), std::nullopt);
    return hover(std::nullopt, std::nullopt);
  }
  if (event.kind == PointerEvent::Press) document_.beginGesture();
  if (event.kind == PointerEvent::Release) {
    document_.endGesture();
    lastUv_.reset();
    lastPoint_.reset();
    return apply({});
  }
  switch (tool_) {
    case CloneTool::SourceOrigin:
      if (!event.hit) return message("Nothing of the source under the pointer");
      return apply(setSourceOrigin(document_, roles_, event.hit->point));
    case CloneTool::PaintCanvas: {
      if (!event.hit) return message("Nothing of the source under the pointer");
      hover(std::nullopt, event.hit);
      const double radius = brushRadius();
      if (lastPoint_ && (*lastPoint_ - event.hit->point).norm() < kDabSpacing * radius) return;
      lastPoint_ = event.hit->point;
      return apply(paintCanvas(document_, roles_, event.hit->point, radius,
                               event.modifiers & Qt::ShiftModifier));
    }
    case CloneTool::PaintRegion:
      return paintRegionAt(view_->source, event);
    case CloneTool::TargetOrigin:
    case CloneTool::MoveTarget:
      return message("The target tools work in the target view");
  }
}

void ClonePanel::targetPointer(const PointerEvent& event) {
  trackPointer(target_, event);
  if (brushResizeEvent(*target_, event)) return;
  if (event.kind == PointerEvent::Leave) return hover(std::nullopt, std::nullopt);
  if (event.kind == PointerEvent::Hover) {
    if (tool_ == CloneTool::PaintRegion && event.hit)
      return hover(uvAt(view_->target, *event.hit), std::nullopt);
    return hover(std::nullopt, std::nullopt);
  }
  if (event.kind == PointerEvent::Press) {
    document_.beginGesture();
    lastPosition_ = event.position;
  }
  if (event.kind == PointerEvent::Release) {
    document_.endGesture();
    lastUv_.reset();
    return apply({});
  }
  switch (tool_) {
    case CloneTool::TargetOrigin: {
      const auto point = event.hit ? onTargetSurface(*event.hit) : std::nullopt;
      if (!point) return message("Nothing of the target under the pointer");
      return apply(setTargetOrigin(document_, roles_, *point));
    }
    case CloneTool::MoveTarget:
      return moveTarget(event);
    case CloneTool::PaintRegion:
      return paintRegionAt(view_->target, event);
    case CloneTool::SourceOrigin:
    case CloneTool::PaintCanvas:
      return message("The source tools work in the source view");
  }
}

void ClonePanel::paintRegionAt(const ShownSurface& surface, const PointerEvent& event) {
  if (!event.hit) return message("Nothing under the brush");
  const auto uv = uvAt(surface, *event.hit);
  if (!uv) return message("The brush is off the canvas: paint where the (u, v) lines are");
  hover(uv, std::nullopt);
  const double radius = brushRadius();
  if (lastUv_ && (*lastUv_ - *uv).norm() < kDabSpacing * radius) return;
  lastUv_ = uv;
  apply(paintRegion(document_, roles_, *uv, radius, event.modifiers & Qt::ShiftModifier));
}

void ClonePanel::moveTarget(const PointerEvent& event) {
  const QPointF delta = event.position - lastPosition_;
  lastPosition_ = event.position;
  if (event.modifiers & Qt::ShiftModifier) {
    if (delta.x() != 0) apply(turnTarget(document_, roles_, kDegreesPerPixel * delta.x()));
    return;
  }
  if (event.modifiers & Qt::ControlModifier) {
    if (delta.y() != 0)
      apply(scaleTarget(document_, roles_, std::exp(-kScalePerPixel * delta.y())));
    return;
  }
  // The origin keeps its place relative to the pointer on the screen, and lands on the surface
  // under that place.
  const auto camera = target_->camera();
  const auto origin = document_.param(roles_.targetMap, "origin");
  if (!camera || !origin || !std::holds_alternative<Vec3>(*origin)) return;
  const Vec3& o = std::get<Vec3>(*origin);
  if (event.kind == PointerEvent::Press) {
    const auto at = camera->project({o[0], o[1], o[2]});
    originOffset_ = at ? QPointF(at->x(), at->y()) - event.position : QPointF();
    return;
  }
  const auto hit = target_->pick(event.position + originOffset_);
  const auto point = hit ? onTargetSurface(*hit) : std::nullopt;
  if (!point) return message("The target canvas cannot leave the surface");
  apply(setTargetOrigin(document_, roles_, *point));
}

std::optional<Eigen::Vector3d> ClonePanel::onTargetSurface(const SurfaceHit& hit) const {
  const auto& values = view_->values;
  if (!values.result || !values.pasteMap) return hit.point;
  const TriMesh& mesh = view_->target.mesh->surface;
  bool target = true;
  for (auto v : mesh.fv_range(mesh.face_handle(hit.face)))
    target = target && values.pasteMap->targetVertex[v.idx()] >= 0;
  if (target) return hit.point;
  // A pasted face: where its (u, v) lies on the target canvas.
  const auto uv = uvAt(view_->target, hit);
  if (!uv || !view_->targetLocator) return std::nullopt;
  return view_->targetLocator->locate(*uv).point;
}

void ClonePanel::hover(const std::optional<Eigen::Vector2d>& uv,
                       const std::optional<SurfaceHit>& canvasHit) {
  hoverUv_ = uv;
  hoverCanvas_ = canvasHit;
  updateOutlines();
}

std::optional<Outline> ClonePanel::brushOutline(const Viewport& view) const {
  const double radius = brushRadius();
  const bool source = &view == source_;
  if (hoverUv_ && tool_ == CloneTool::PaintRegion) {
    // The same disc of the shared domain on both canvases.
    const auto& locator = source ? view_->sourceLocator : view_->targetLocator;
    if (locator) return Outline{domainCircle(*locator, *hoverUv_, radius), kBrush, 2};
  }
  if (hoverCanvas_ && tool_ == CloneTool::PaintCanvas && source)
    return tangentCircle(*hoverCanvas_, radius, kEraser);
  return std::nullopt;
}

void ClonePanel::updateOutlines() {
  std::vector<Outline> onSource, onTarget;
  const double radius = brushRadius();
  const auto& values = view_->values;
  const bool axes = axesAction_->isChecked();
  if (values.sourceMap && axes) {
    for (Outline& o : originMarker(values.sourceMap->origin, 2 * radius))
      onSource.push_back(std::move(o));
  }
  if (values.targetMap && axes) {
    for (Outline& o : originMarker(values.targetMap->origin, 2 * radius * values.targetMap->scale))
      onTarget.push_back(std::move(o));
  }
  if (auto brush = brushOutline(*source_)) onSource.push_back(std::move(*brush));
  if (auto brush = brushOutline(*target_)) onTarget.push_back(std::move(*brush));
  source_->setOutlines(std::move(onSource));
  target_->setOutlines(std::move(onTarget));
}

}  // namespace geobrush::studio
