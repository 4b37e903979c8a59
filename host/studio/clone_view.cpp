#include "clone_view.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <limits>

#include "uv_lines.hpp"

namespace geobrush::studio {
namespace {

const Endpoint* sourceOf(const Graph& graph, const std::string& node, const std::string& port) {
  for (const auto& c : graph.connections)
    if (c.to.node == node && c.to.port == port) return &c.from;
  return nullptr;
}

std::string typeOf(const Graph& graph, const std::string& node) {
  auto it = graph.nodes.find(node);
  return it == graph.nodes.end() ? std::string() : it->second.type;
}

template <typename T>
std::shared_ptr<const T> outputAs(const Evaluator& evaluator, const Endpoint& at) {
  if (at.node.empty()) return nullptr;
  return std::dynamic_pointer_cast<const T>(evaluator.output(at.node, at.port));
}

const Rgb kSurface{0.80f, 0.80f, 0.80f};
const Rgb kRegionTint{0.95f, 0.55f, 0.15f};

Rgb tinted(const Rgb& color) {
  Rgb mixed;
  for (int c = 0; c < 3; ++c)
    mixed[c] = 0.55f * color[c] + 0.45f * kRegionTint[c];
  return mixed;
}

const Eigen::Vector2d kOffCanvas(std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::quiet_NaN());

// Canvas vertex -> colour of its (u, v) lines, with the spacing given (so that the source and
// target lines continue into each other) or chosen from the source canvas.
std::vector<Rgb> lineColors(const Parameterization& map, double& spacing) {
  UvLinesOptions options;
  options.spacing = spacing;
  options.surface = kSurface;
  UvLinesResult lines = paintUvLines(map, options);
  spacing = lines.spacing;
  return std::move(lines.mesh.vertexColors);
}

// Paints the vertices in the strokes' region with the tint.
void tintRegion(ShownSurface& shown, std::vector<Rgb>& colors, const Strokes* strokes) {
  if (!strokes) return;
  for (std::size_t v = 0; v < colors.size(); ++v)
    if (shown.uv[v].allFinite() && strokes->contains(shown.uv[v])) colors[v] = tinted(colors[v]);
}

double sourceSpacing(const CloneValues& values) {
  double spacing = 0;
  if (values.sourceMap) lineColors(*values.sourceMap, spacing);
  return spacing;
}

}  // namespace

std::vector<std::string> CloneRoles::liveTargets() const {
  std::vector<std::string> targets;
  for (const std::string* node : {&paste, &roi, &sourceMap, &targetMap})
    if (!node->empty()) targets.push_back(*node);
  return targets;
}

CloneRoles findClone(const Graph& graph, const std::string& preferredRoi) {
  CloneRoles roles;
  if (typeOf(graph, preferredRoi) == "geobrush.roi") {
    roles.roi = preferredRoi;
  } else {
    for (const auto& [name, node] : graph.nodes)
      if (node.type == "geobrush.roi") {
        roles.roi = name;
        break;
      }
  }
  if (roles.roi.empty()) return roles;

  if (const Endpoint* from = sourceOf(graph, roles.roi, "source")) roles.sourceMap = from->node;
  if (const Endpoint* from = sourceOf(graph, roles.roi, "target")) roles.targetMap = from->node;
  if (const Endpoint* from = sourceOf(graph, roles.roi, "strokes")) roles.roiStrokes = *from;
  // The strokes may pass through ROI correction (or any node with a strokes input) first.
  for (const Endpoint* from = sourceOf(graph, roles.roi, "strokes"); from;
       from = sourceOf(graph, from->node, "strokes")) {
    if (typeOf(graph, from->node) == "geobrush.strokes") {
      roles.strokes = from->node;
      break;
    }
  }
  if (const Endpoint* from = sourceOf(graph, roles.sourceMap, "canvas");
      from && typeOf(graph, from->node) == "geobrush.canvas_grow") {
    roles.sourceCanvas = from->node;
    if (const Endpoint* mesh = sourceOf(graph, roles.sourceCanvas, "mesh"))
      roles.sourceMesh = *mesh;
  }
  if (const Endpoint* mesh = sourceOf(graph, roles.targetMap, "mesh")) roles.targetMesh = *mesh;
  for (const auto& c : graph.connections) {
    if (c.from.node != roles.roi || c.from.port != "region") continue;
    const std::string type = typeOf(graph, c.to.node);
    if (type == "geobrush.stitch" || type == "geobrush.variational_paste") {
      roles.paste = c.to.node;
      break;
    }
  }
  return roles;
}

CloneValues fetchClone(const Evaluator& evaluator, const CloneRoles& roles) {
  CloneValues values;
  values.sourceMesh = outputAs<Mesh>(evaluator, roles.sourceMesh);
  values.targetMesh = outputAs<Mesh>(evaluator, roles.targetMesh);
  values.canvas = outputAs<Canvas>(evaluator, {roles.sourceCanvas, "canvas"});
  values.sourceMap = outputAs<Parameterization>(evaluator, {roles.sourceMap, "parameterization"});
  values.targetMap = outputAs<Parameterization>(evaluator, {roles.targetMap, "parameterization"});
  values.strokes = outputAs<Strokes>(evaluator, roles.roiStrokes);
  values.result = outputAs<Mesh>(evaluator, {roles.paste, "mesh"});
  values.pasteMap = outputAs<PasteMap>(evaluator, {roles.paste, "map"});
  // A map of an older result (the paste failed this time) must not colour a newer mesh.
  if (!values.result || !values.pasteMap ||
      values.pasteMap->targetVertex.size() != values.result->surface.n_vertices()) {
    values.result = nullptr;
    values.pasteMap = nullptr;
  }
  return values;
}

ShownSurface showSource(const CloneValues& values) {
  ShownSurface shown;
  if (!values.sourceMesh) return shown;
  const TriMesh& surface = values.sourceMesh->surface;
  std::vector<Rgb> colors(surface.n_vertices(), kSurface);
  shown.uv.assign(surface.n_vertices(), kOffCanvas);
  const Parameterization* map = values.sourceMap.get();
  if (map && map->canvas && map->canvas->source == values.sourceMesh) {
    double spacing = 0;
    const std::vector<Rgb> lines = lineColors(*map, spacing);
    const std::vector<int>& toSource = map->canvas->sourceVertex;
    for (std::size_t v = 0; v < toSource.size(); ++v) {
      colors[toSource[v]] = lines[v];
      shown.uv[toSource[v]] = map->uv[v];
    }
  }
  tintRegion(shown, colors, values.strokes.get());
  shown.mesh = std::make_shared<const Mesh>(surface, std::move(colors));
  return shown;
}

ShownSurface showTarget(const CloneValues& values) {
  ShownSurface shown;
  const MeshPtr& mesh = values.result ? values.result : values.targetMesh;
  if (!mesh) return shown;
  const std::size_t count = mesh->surface.n_vertices();
  std::vector<Rgb> colors(count, kSurface);
  shown.uv.assign(count, kOffCanvas);

  // Target mesh vertex -> (colour, uv) of the target canvas, where it has one.
  double spacing = sourceSpacing(values);
  const Parameterization* target = values.targetMap.get();
  const bool targetMatches =
      target && target->canvas && target->canvas->source == values.targetMesh && values.targetMesh;
  std::vector<int> targetCanvasVertex;
  std::vector<Rgb> targetLines;
  if (targetMatches) {
    targetLines = lineColors(*target, spacing);
    targetCanvasVertex.assign(values.targetMesh->surface.n_vertices(), -1);
    for (std::size_t v = 0; v < target->canvas->sourceVertex.size(); ++v)
      targetCanvasVertex[target->canvas->sourceVertex[v]] = int(v);
  }
  auto fromTarget = [&](std::size_t shownVertex, int targetVertex) {
    if (targetVertex < 0 || targetCanvasVertex.empty()) return;
    const int canvasVertex = targetCanvasVertex[targetVertex];
    if (canvasVertex < 0) return;
    colors[shownVertex] = targetLines[canvasVertex];
    shown.uv[shownVertex] = target->uv[canvasVertex];
  };

  if (values.result) {
    std::vector<Rgb> sourceLines;
    const Parameterization* source = values.sourceMap.get();
    if (source) sourceLines = lineColors(*source, spacing);
    const PasteMap& map = *values.pasteMap;
    for (std::size_t v = 0; v < count; ++v) {
      if (map.targetVertex[v] >= 0) {
        fromTarget(v, map.targetVertex[v]);
      } else if (source && map.sourceVertex[v] >= 0 &&
                 std::size_t(map.sourceVertex[v]) < source->uv.size()) {
        colors[v] = sourceLines[map.sourceVertex[v]];
        shown.uv[v] = source->uv[map.sourceVertex[v]];
      }
    }
  } else {
    for (std::size_t v = 0; v < count; ++v)
      fromTarget(v, int(v));
  }
  tintRegion(shown, colors, values.strokes.get());
  shown.mesh = std::make_shared<const Mesh>(mesh->surface, std::move(colors));
  return shown;
}

std::optional<SurfaceHit> castRay(const TriMesh& mesh, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction) {
  // Moeller-Trumbore, both sides of every face.
  std::optional<SurfaceHit> nearest;
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    int k = 0;
    for (auto v : mesh.fv_range(f)) {
      const auto& q = mesh.point(v);
      p[k++] = {q[0], q[1], q[2]};
    }
    const Eigen::Vector3d e1 = p[1] - p[0], e2 = p[2] - p[0];
    const Eigen::Vector3d h = direction.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-300) continue;
    const Eigen::Vector3d s = origin - p[0];
    const double b1 = s.dot(h) / det;
    if (b1 < 0 || b1 > 1) continue;
    const Eigen::Vector3d q = s.cross(e1);
    const double b2 = direction.dot(q) / det;
    if (b2 < 0 || b1 + b2 > 1) continue;
    const double t = e2.dot(q) / det;
    if (t <= 0 || (nearest && t >= nearest->distance)) continue;
    SurfaceHit hit;
    hit.face = f.idx();
    hit.distance = t;
    hit.point = origin + t * direction;
    hit.barycentric = {1 - b1 - b2, b1, b2};
    hit.normal = e1.cross(e2).normalized();
    if (hit.normal.dot(direction) > 0) hit.normal = -hit.normal;
    nearest = hit;
  }
  return nearest;
}

std::optional<Eigen::Vector2d> uvAt(const ShownSurface& surface, const SurfaceHit& hit) {
  if (!surface.mesh || hit.face < 0) return std::nullopt;
  const TriMesh& mesh = surface.mesh->surface;
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  int k = 0;
  for (auto v : mesh.fv_range(mesh.face_handle(hit.face))) {
    const Eigen::Vector2d& corner = surface.uv[v.idx()];
    if (!corner.allFinite()) return std::nullopt;
    uv += hit.barycentric[k++] * corner;
  }
  return uv;
}

std::vector<Eigen::Vector3d> domainCircle(const DomainLocator& locator,
                                          const Eigen::Vector2d& center, double radius,
                                          int segments) {
  std::vector<Eigen::Vector3d> points;
  points.reserve(segments + 1);
  for (int i = 0; i <= segments; ++i) {
    const double angle = 2 * M_PI * i / segments;
    const DomainHit hit =
        locator.locate(center + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
    points.push_back(hit.point);
  }
  return points;
}

}  // namespace geobrush::studio
