// A 3D view of one surface, drawn by the core renderer (the same as `geobrush render`), with
// outlines drawn over it (brush circles, canvas origins). The right button orbits, the middle
// button (or Shift + right) pans, the wheel zooms; the left button belongs to the tools, which
// get each press, move and release with the surface point under the pointer. The wheel zooms
// toward the point under the pointer, which stays where it is on the screen.
#pragma once

#include <Eigen/Geometry>
#include <QColor>
#include <QImage>
#include <QWidget>
#include <functional>
#include <optional>

#include "clone_view.hpp"
#include "geobrush/field_colors.hpp"
#include "geobrush/render.hpp"

namespace geobrush::studio {

struct PointerEvent {
  enum Kind { Press, Move, Release, Hover, Leave } kind = Hover;
  QPointF position;
  Qt::KeyboardModifiers modifiers;
  std::optional<SurfaceHit> hit;  // on the shown surface
};

// A polyline in world coordinates drawn over the surface.
struct Outline {
  std::vector<Eigen::Vector3d> points;
  QColor color;
  double width = 2;
};

// Segments lying on the surface (two ends each), drawn where their face turns towards the eye.
struct SurfaceLines {
  const CoordinateLines::Set* segments = nullptr;  // owned by the caller, kept while shown
  QColor color;
};

// A colour bar drawn at the bottom left: what the surface's colours mean.
struct Legend {
  std::string name;
  FieldRange range;
  bool operator==(const Legend&) const = default;
};

class Viewport : public QWidget {
  Q_OBJECT

 public:
  explicit Viewport(const QString& title, QWidget* parent = nullptr);

  // The surface to show. The camera frames the first surface shown, and keeps that frame for
  // the next ones, so that a changing result does not move the view. `drawn`, the surface's
  // render geometry prepared ahead (Renderer::prepare), spares the next frame that work. The
  // same mesh value shown again is not drawn again.
  void setSurface(ShownSurface surface, const Renderer::Prepared& drawn = nullptr);
  const ShownSurface& surface() const { return surface_; }
  void setOutlines(std::vector<Outline> outlines);
  void setLines(std::vector<SurfaceLines> lines);
  const std::vector<Outline>& outlines() const { return outlines_; }
  const std::vector<SurfaceLines>& lines() const { return lines_; }
  void setLegend(std::optional<Legend> legend);
  const std::optional<Legend>& legend() const { return legend_; }
  // A line of text drawn beside a window position (the brush radius while it is resized).
  struct Note {
    QPointF at;
    QString text;
  };
  void setNote(std::optional<Note> note);
  const std::optional<Note>& note() const { return note_; }
  // Frames the shown surface again, from the default direction.
  void resetView();
  // Frames the box (a part of the surface: the paste, the canvas), looking from where the view
  // looks now; the pan and zoom start over.
  void frameBox(const Eigen::AlignedBox3d& box);
  // Frames the whole surface, looking from where the view looks now.
  void frameAll();
  const std::optional<RenderFrame>& frame() const { return frame_; }
  // The triangles' edges drawn over the shading.
  void setWireframe(bool wireframe);
  bool wireframe() const { return wireframe_; }
  const RenderView& view() const { return view_; }
  // The camera of the current size and view; none without a surface. Kept until the surface,
  // the view or the size changes: each pointer move picks with it.
  std::optional<RenderCamera> camera() const;
  // The surface point under a window position.
  std::optional<SurfaceHit> pick(const QPointF& position) const;
  // The last rendered image (without outlines).
  const QImage& image() const { return image_; }
  // How many frames built their surface's render geometry themselves rather than finding it
  // prepared or kept (for tests).
  std::size_t geometryBuilds() const { return renderer_.geometryBuilds(); }

  std::function<void(const PointerEvent&)> onPointer;

 protected:
  void paintEvent(QPaintEvent*) override;
  void resizeEvent(QResizeEvent*) override;
  void mousePressEvent(QMouseEvent*) override;
  void mouseMoveEvent(QMouseEvent*) override;
  void mouseReleaseEvent(QMouseEvent*) override;
  void wheelEvent(QWheelEvent*) override;
  void leaveEvent(QEvent*) override;

 private:
  RenderOptions renderOptions() const;
  // Frame radii per pixel at the zoom (what a pan by one pixel moves).
  double radiiPerPixel(double zoom) const;
  void changed();  // the picture must be rendered again
  void pointer(PointerEvent::Kind kind, const QPointF& position, Qt::KeyboardModifiers modifiers);

  QString title_;
  ShownSurface surface_;
  std::optional<Legend> legend_;
  std::optional<Note> note_;
  std::optional<RenderFrame> frame_;
  RenderView view_;
  std::vector<Outline> outlines_;
  std::vector<SurfaceLines> lines_;
  QImage image_;
  bool stale_ = true;
  // Keeps the shown mesh's geometry from frame to frame: an orbit redraws for the camera alone.
  mutable Renderer renderer_;
  mutable bool cameraKnown_ = false;  // camera_ was computed since the last change
  mutable std::optional<RenderCamera> camera_;
  QString error_;
  // Camera drags: the button held and where the pointer was.
  Qt::MouseButton dragButton_ = Qt::NoButton;
  QPointF lastPosition_;
  bool toolDrag_ = false;
  bool wireframe_ = false;
};

}  // namespace geobrush::studio
