#include "viewport.hpp"

#include <Eigen/Geometry>
#include <QMouseEvent>
#include <QPainter>
#include <QPainterPath>
#include <QVector>
#include <QWheelEvent>
#include <algorithm>
#include <cmath>

namespace geobrush::studio {
namespace {

const RenderView kDefaultView{.azimuthDeg = 30, .elevationDeg = 20, .fovDeg = 35, .zoom = 1.2};
const Rgb kBackground{0.16f, 0.17f, 0.19f};

RenderFrame frameOf(const Eigen::AlignedBox3d& box) {
  const Eigen::Vector3d centre = box.center();
  return {{centre.x(), centre.y(), centre.z()}, std::max(0.5 * box.diagonal().norm(), 1e-9)};
}

RenderFrame frameOf(const TriMesh& mesh) {
  return frameOf(boundsOf(mesh));
}

}  // namespace

Viewport::Viewport(const QString& title, QWidget* parent)
    : QWidget(parent), title_(title), view_(kDefaultView) {
  setMinimumSize(240, 200);
  setMouseTracking(true);
  setFocusPolicy(Qt::ClickFocus);
  setAttribute(Qt::WA_OpaquePaintEvent);
}

void Viewport::setSurface(ShownSurface surface, const Renderer::Prepared& drawn) {
  renderer_.keep(drawn);
  const bool sameMesh = surface.mesh == surface_.mesh;
  surface_ = std::move(surface);
  if (!frame_ && surface_.mesh && surface_.mesh->surface.n_faces() > 0)
    frame_ = frameOf(surface_.mesh->surface);
  if (!sameMesh) changed();
}

void Viewport::setOutlines(std::vector<Outline> outlines) {
  outlines_ = std::move(outlines);
  update();
}

void Viewport::setNote(std::optional<Note> note) {
  note_ = std::move(note);
  update();
}

void Viewport::setLines(std::vector<SurfaceLines> lines) {
  lines_ = std::move(lines);
  update();
}

void Viewport::resetView() {
  view_ = kDefaultView;
  frame_.reset();
  if (surface_.mesh && surface_.mesh->surface.n_faces() > 0)
    frame_ = frameOf(surface_.mesh->surface);
  changed();
}

double Viewport::radiiPerPixel(double zoom) const {
  RenderView view = view_;
  view.zoom = zoom;
  return framedRadiiPerPixel(view, std::max(width(), 1), std::max(height(), 1));
}

void Viewport::frameBox(const Eigen::AlignedBox3d& box) {
  if (box.isEmpty()) return;
  frame_ = frameOf(box);
  view_.zoom = 1;
  view_.panRight = view_.panUp = 0;
  changed();
}

void Viewport::setWireframe(bool wireframe) {
  if (wireframe == wireframe_) return;
  wireframe_ = wireframe;
  changed();
}

void Viewport::frameAll() {
  if (surface_.mesh && surface_.mesh->surface.n_faces() > 0)
    frameBox(boundsOf(surface_.mesh->surface));
}

RenderOptions Viewport::renderOptions() const {
  RenderOptions options;
  options.width = std::max(width(), 1);
  options.height = std::max(height(), 1);
  options.view = view_;
  options.background = kBackground;
  options.frame = frame_;
  return options;
}

std::optional<RenderCamera> Viewport::camera() const {
  if (cameraKnown_) return camera_;
  cameraKnown_ = true;
  camera_.reset();
  if (surface_.mesh && surface_.mesh->surface.n_faces() > 0) {
    try {
      camera_ = renderer_.camera({{surface_.mesh}}, renderOptions());
    } catch (const std::exception&) {
      // Nothing drawable: no camera, as without a surface.
    }
  }
  return camera_;
}

std::optional<SurfaceHit> Viewport::pick(const QPointF& position) const {
  const auto cam = camera();
  if (!cam) return std::nullopt;
  // Pixel centres: the renderer samples each pixel at its middle.
  const auto [origin, direction] = cam->ray(position.x() + 0.5, position.y() + 0.5);
  return castRay(surface_.mesh->surface, origin, direction);
}

void Viewport::setLegend(std::optional<Legend> legend) {
  if (legend == legend_) return;
  legend_ = std::move(legend);
  changed();
}

void Viewport::changed() {
  stale_ = true;
  cameraKnown_ = false;
  update();
}

void Viewport::paintEvent(QPaintEvent*) {
  QPainter painter(this);
  if (stale_ && surface_.mesh && surface_.mesh->surface.n_faces() > 0) {
    try {
      RenderItem item{surface_.mesh};
      item.wireframe = wireframe_;
      Image rendered = renderer_.render({item}, renderOptions()).image;
      if (legend_) drawFieldLegend(rendered, legend_->name, legend_->range);
      image_ =
          QImage(rendered.rgba.data(), rendered.width, rendered.height, QImage::Format_RGBA8888)
              .copy();
      error_.clear();
    } catch (const std::exception& e) {
      error_ = QString::fromStdString(e.what());
    }
    stale_ = false;
  }
  if (!surface_.mesh) {
    painter.fillRect(rect(), QColor(41, 43, 48));
    image_ = QImage();
  } else {
    painter.drawImage(0, 0, image_);
  }

  painter.setRenderHint(QPainter::Antialiasing);
  if (const auto cam = camera()) {
    for (const SurfaceLines& lines : lines_) {
      if (!lines.segments) continue;
      const auto& ends = lines.segments->ends;
      const auto& normals = lines.segments->normals;
      QVector<QLineF> visible;
      for (std::size_t i = 0; i < normals.size(); ++i) {
        const Eigen::Vector3d& a = ends[2 * i];
        const Eigen::Vector3d& b = ends[2 * i + 1];
        if (normals[i].dot(cam->eye - 0.5 * (a + b)) <= 0) continue;
        const auto pa = cam->project(a), pb = cam->project(b);
        if (pa && pb) visible.push_back({QPointF(pa->x(), pa->y()), QPointF(pb->x(), pb->y())});
      }
      painter.setPen(QPen(lines.color, 1.3));
      painter.drawLines(visible);
    }
    for (const Outline& outline : outlines_) {
      QPainterPath path;
      bool open = false;
      for (const Eigen::Vector3d& point : outline.points) {
        // A gap (NaN) or a point behind the eye breaks the line.
        const auto at = point.allFinite() ? cam->project(point) : std::nullopt;
        if (!at) {
          open = false;
          continue;
        }
        const QPointF p(at->x(), at->y());
        if (open)
          path.lineTo(p);
        else
          path.moveTo(p);
        open = true;
      }
      painter.setPen(QPen(outline.color, outline.width));
      painter.drawPath(path);
    }
  }
  if (note_) {
    // On a dark box, below and to the right of the point, kept inside the view.
    QRectF box = painter.fontMetrics().boundingRect(note_->text).adjusted(-4, -2, 4, 2);
    box.moveTopLeft(note_->at + QPointF(14, 14));
    box.moveRight(std::min(box.right(), double(width() - 2)));
    box.moveBottom(std::min(box.bottom(), double(height() - 2)));
    painter.fillRect(box, QColor(20, 20, 24, 200));
    painter.setPen(QColor(255, 220, 160));
    painter.drawText(box, Qt::AlignCenter, note_->text);
  }
  painter.setPen(QColor(230, 230, 230));
  painter.drawText(rect().adjusted(8, 6, -8, -6), Qt::AlignLeft | Qt::AlignTop, title_);
  if (!error_.isEmpty())
    painter.drawText(rect().adjusted(8, 6, -8, -6), Qt::AlignLeft | Qt::AlignBottom, error_);
  else if (!surface_.mesh)
    painter.drawText(rect(), Qt::AlignCenter, "Nothing to show yet");
}

void Viewport::resizeEvent(QResizeEvent*) {
  changed();
}

void Viewport::pointer(PointerEvent::Kind kind, const QPointF& position,
                       Qt::KeyboardModifiers modifiers) {
  if (!onPointer) return;
  PointerEvent event;
  event.kind = kind;
  event.position = position;
  event.modifiers = modifiers;
  if (kind != PointerEvent::Leave) event.hit = pick(position);
  onPointer(event);
}

void Viewport::mousePressEvent(QMouseEvent* event) {
  lastPosition_ = event->position();
  if (event->button() == Qt::LeftButton) {
    toolDrag_ = true;
    pointer(PointerEvent::Press, event->position(), event->modifiers());
    return;
  }
  dragButton_ = event->button();
}

void Viewport::mouseMoveEvent(QMouseEvent* event) {
  const QPointF delta = event->position() - lastPosition_;
  lastPosition_ = event->position();
  if (toolDrag_) {
    pointer(PointerEvent::Move, event->position(), event->modifiers());
    return;
  }
  if (dragButton_ == Qt::NoButton) {
    pointer(PointerEvent::Hover, event->position(), event->modifiers());
    return;
  }
  const bool pan = dragButton_ == Qt::MiddleButton ||
                   (dragButton_ == Qt::RightButton && (event->modifiers() & Qt::ShiftModifier));
  if (pan) {
    const double perPixel = radiiPerPixel(view_.zoom);
    view_.panRight -= delta.x() * perPixel;
    view_.panUp += delta.y() * perPixel;
  } else {
    view_.azimuthDeg -= 0.4 * delta.x();
    view_.elevationDeg = std::clamp(view_.elevationDeg + 0.4 * delta.y(), -89.0, 89.0);
  }
  changed();
}

void Viewport::mouseReleaseEvent(QMouseEvent* event) {
  if (event->button() == Qt::LeftButton && toolDrag_) {
    toolDrag_ = false;
    pointer(PointerEvent::Release, event->position(), event->modifiers());
    return;
  }
  if (event->button() == dragButton_) dragButton_ = Qt::NoButton;
}

// The pan moves by the pointer's offset from the centre times the change in frame radii per
// pixel, so that the point under the pointer stays under it (exactly in the plane of the frame's
// centre, nearly elsewhere).
void Viewport::wheelEvent(QWheelEvent* event) {
  const double steps = event->angleDelta().y() / 120.0;
  const double zoom = std::clamp(view_.zoom * std::pow(1.15, steps), 0.05, 200.0);
  const double perPixelChange = radiiPerPixel(view_.zoom) - radiiPerPixel(zoom);
  const QPointF offset = event->position() - QPointF(width() / 2.0, height() / 2.0);
  view_.panRight += offset.x() * perPixelChange;
  view_.panUp -= offset.y() * perPixelChange;
  view_.zoom = zoom;
  changed();
}

void Viewport::leaveEvent(QEvent*) {
  pointer(PointerEvent::Leave, {}, {});
}

}  // namespace geobrush::studio
