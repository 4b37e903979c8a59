#include "clone_view.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <set>

namespace geobrush::studio {
namespace {

// The output feeding an input port, if any.
const Endpoint* sourceOf(const Graph& graph, const std::string& node, const std::string& port) {
  const Connection* connection = graph.source(node, port);
  return connection ? &connection->from : nullptr;
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

const Rgb kSurface{0.78f, 0.78f, 0.80f};
const Rgb kCanvas{0.90f, 0.88f, 0.80f};
const Rgb kRegionTint{0.95f, 0.55f, 0.15f};

Rgb tinted(const Rgb& color) {
  Rgb mixed;
  for (int c = 0; c < 3; ++c)
    mixed[c] = 0.55f * color[c] + 0.45f * kRegionTint[c];
  return mixed;
}

const Eigen::Vector2d kOffCanvas(std::numeric_limits<double>::quiet_NaN(),
                                 std::numeric_limits<double>::quiet_NaN());
const Eigen::Vector3d kOffCanvas3 =
    Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());

// Canvas vertices in the canvas colour, the painted region tinted, the rest plain.
MeshPtr colored(const TriMesh& surface, const std::vector<Eigen::Vector2d>& uv,
                const Strokes* strokes) {
  std::vector<Rgb> colors(surface.n_vertices(), kSurface);
  for (std::size_t v = 0; v < colors.size(); ++v) {
    if (!uv[v].allFinite()) continue;
    colors[v] = strokes && strokes->contains(uv[v]) ? tinted(kCanvas) : kCanvas;
  }
  return std::make_shared<const Mesh>(surface, std::move(colors));
}

// Where the segment from a to b crosses `level` of a linear function with values fa, fb.
Eigen::Vector3d crossing(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double fa, double fb,
                         double level) {
  return a + (level - fa) / (fb - fa) * (b - a);
}

}  // namespace

Eigen::AlignedBox3d boundsOf(const TriMesh& mesh) {
  Eigen::AlignedBox3d box;
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    box.extend(Eigen::Vector3d(p[0], p[1], p[2]));
  }
  return box;
}

namespace {

// The first node downstream of `start` (breadth first, names in order) whose outputs "mesh" and
// "map" are both used: a paste that does not read the region itself, such as EMD detail
// transfer's belt smoothing at the end of its chain.
std::string pasteDownstreamOf(const Graph& graph, const std::string& start) {
  std::vector<std::string> frontier{start};
  std::set<std::string> seen{start};
  while (!frontier.empty()) {
    std::vector<std::string> next;
    for (const auto& c : graph.connections)
      if (std::find(frontier.begin(), frontier.end(), c.from.node) != frontier.end() &&
          seen.insert(c.to.node).second)
        next.push_back(c.to.node);
    std::sort(next.begin(), next.end());
    for (const std::string& node : next) {
      bool mesh = false, map = false;
      for (const auto& c : graph.connections)
        if (c.from.node == node) {
          mesh = mesh || c.from.port == "mesh";
          map = map || c.from.port == "map";
        }
      if (mesh && map) return node;
    }
    frontier = std::move(next);
  }
  return {};
}

}  // namespace

bool isRoiType(const std::string& type) {
  return type == "geobrush.roi" || type == "geobrush.texture_roi";
}

bool isPasteType(const std::string& type) {
  return type == "geobrush.stitch" || type == "geobrush.variational_paste" ||
         type == "geobrush.cdt_stitch";
}

std::vector<std::string> CloneRoles::liveTargets() const {
  std::vector<std::string> targets;
  for (const std::string* node : {&paste, &roi, &sourceMap, &targetMap})
    if (!node->empty()) targets.push_back(*node);
  return targets;
}

CloneRoles findClone(const Graph& graph, const std::string& preferredRoi) {
  CloneRoles roles;
  if (isRoiType(typeOf(graph, preferredRoi))) {
    roles.roi = preferredRoi;
  } else {
    for (const auto& [name, node] : graph.nodes)
      if (isRoiType(node.type)) {
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
    if (isPasteType(typeOf(graph, c.to.node))) {
      roles.paste = c.to.node;
      break;
    }
  }
  if (roles.paste.empty()) roles.paste = pasteDownstreamOf(graph, roles.roi);
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
  shown.uv.assign(surface.n_vertices(), kOffCanvas);
  const Parameterization* map = values.sourceMap.get();
  if (map && map->canvas && map->canvas->source == values.sourceMesh) {
    const std::vector<int>& toSource = map->canvas->sourceVertex;
    for (std::size_t v = 0; v < toSource.size(); ++v)
      shown.uv[toSource[v]] = map->uv[v];
  }
  shown.mesh = colored(surface, shown.uv, values.strokes.get());
  return shown;
}

ShownSurface showTarget(const CloneValues& values) {
  ShownSurface shown;
  const MeshPtr& mesh = values.result ? values.result : values.targetMesh;
  if (!mesh) return shown;
  const std::size_t count = mesh->surface.n_vertices();
  shown.uv.assign(count, kOffCanvas);

  // Target mesh vertex -> its uv on the target canvas, where it has one.
  const Parameterization* target = values.targetMap.get();
  std::vector<int> targetCanvasVertex;
  if (target && target->canvas && values.targetMesh &&
      target->canvas->source == values.targetMesh) {
    targetCanvasVertex.assign(values.targetMesh->surface.n_vertices(), -1);
    for (std::size_t v = 0; v < target->canvas->sourceVertex.size(); ++v)
      targetCanvasVertex[target->canvas->sourceVertex[v]] = int(v);
  }
  auto fromTarget = [&](std::size_t shownVertex, int targetVertex) {
    if (targetVertex < 0 || targetCanvasVertex.empty()) return;
    if (const int canvasVertex = targetCanvasVertex[targetVertex]; canvasVertex >= 0)
      shown.uv[shownVertex] = target->uv[canvasVertex];
  };
  if (values.result) {
    // The pasted part continues the target canvas's lines with the source canvas's: both are in
    // the shared domain.
    const Parameterization* source = values.sourceMap.get();
    const PasteMap& map = *values.pasteMap;
    for (std::size_t v = 0; v < count; ++v) {
      if (map.targetVertex[v] >= 0)
        fromTarget(v, map.targetVertex[v]);
      else if (source && map.sourceVertex[v] >= 0 &&
               std::size_t(map.sourceVertex[v]) < source->uv.size())
        shown.uv[v] = source->uv[map.sourceVertex[v]];
    }
  } else {
    for (std::size_t v = 0; v < count; ++v)
      fromTarget(v, int(v));
  }
  shown.mesh = colored(mesh->surface, shown.uv, values.strokes.get());
  return shown;
}

double lineSpacing(const CloneValues& values) {
  if (!values.sourceMap || values.sourceMap->uv.empty()) return 0;
  Eigen::Vector2d lo = values.sourceMap->uv.front(), hi = lo;
  for (const Eigen::Vector2d& p : values.sourceMap->uv) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return (hi - lo).maxCoeff() / 10;
}

CoordinateLines coordinateLines(const ShownSurface& surface, double spacing) {
  CoordinateLines lines;
  if (!surface.mesh || !(spacing > 0)) return lines;
  const TriMesh& mesh = surface.mesh->surface;
  for (auto f : mesh.faces()) {
    std::array<Eigen::Vector3d, 3> p;
    std::array<Eigen::Vector2d, 3> uv;
    int k = 0;
    bool onCanvas = true;
    for (auto v : mesh.fv_range(f)) {
      const auto& q = mesh.point(v);
      p[k] = {q[0], q[1], q[2]};
      uv[k++] = surface.uv[v.idx()];
      onCanvas = onCanvas && uv[k - 1].allFinite();
    }
    if (!onCanvas) continue;
    const Eigen::Vector3d normal = (p[1] - p[0]).cross(p[2] - p[0]).normalized();
    for (int axis = 0; axis < 2; ++axis) {
      const std::array<double, 3> f3 = {uv[0][axis], uv[1][axis], uv[2][axis]};
      const double lo = std::min({f3[0], f3[1], f3[2]}), hi = std::max({f3[0], f3[1], f3[2]});
      for (double line = std::ceil(lo / spacing); line * spacing <= hi; ++line) {
        const double level = line * spacing;
        // The level set crosses the two edges whose ends lie on either side (a corner on the
        // level counts as above it, so each crossing is found once).
        std::vector<Eigen::Vector3d> ends;
        for (int e = 0; e < 3; ++e) {
          const int a = e, b = (e + 1) % 3;
          if ((f3[a] >= level) != (f3[b] >= level))
            ends.push_back(crossing(p[a], p[b], f3[a], f3[b], level));
        }
        if (ends.size() != 2) continue;
        CoordinateLines::Set& set = axis == 0 ? lines.u : lines.v;
        set.ends.push_back(ends[0]);
        set.ends.push_back(ends[1]);
        set.normals.push_back(normal);
      }
    }
  }
  return lines;
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
    points.push_back(hit.inside ? hit.point : kOffCanvas3);
  }
  return points;
}

std::vector<FieldLayer> fieldLayers(const Graph& graph, const NodeRegistry& registry,
                                    const Evaluator& evaluator) {
  std::vector<FieldLayer> layers;
  for (const auto& [name, node] : graph.nodes) {
    const NodeType* type = registry.find(node.type);
    if (!type) continue;
    for (const PortDecl& port : type->outputs) {
      if (port.typeId != VertexFields::kTypeId) continue;
      const auto fields =
          std::dynamic_pointer_cast<const VertexFields>(evaluator.output(name, port.name));
      if (!fields) continue;
      for (const auto& column : fields->names())
        layers.push_back({name, port.name, column, fields});
    }
  }
  return layers;
}

std::optional<ShownSurface> colouredBy(const ShownSurface& surface, const FieldLayer& layer,
                                       FieldRange* range) {
  const auto* values = layer.fields ? layer.fields->find(layer.column) : nullptr;
  if (!surface.mesh || !values || values->size() != surface.mesh->surface.n_vertices())
    return std::nullopt;
  *range = fieldRange(*values);
  ShownSurface coloured = surface;
  coloured.mesh = std::make_shared<const Mesh>(surface.mesh->surface, fieldColors(*values, *range));
  return coloured;
}

}  // namespace geobrush::studio
