#include "geobrush/clone.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <set>

#include "geobrush/registry.hpp"
#include "geobrush/surface_point.hpp"
#include "geobrush/text.hpp"

namespace geobrush {
namespace {

namespace fs = std::filesystem;

constexpr const char* kRoleNodes[] = {"source_mesh", "source_canvas", "target_mesh",
                                      "target_map",  "strokes",       "save_result"};

std::vector<fs::path> splitPathList(const char* list) {
  std::vector<fs::path> dirs;
  const std::string text = list ? list : "";
  for (std::size_t start = 0; start < text.size();) {
    const std::size_t colon = std::min(text.find(':', start), text.size());
    if (colon > start) dirs.emplace_back(text.substr(start, colon - start));
    start = colon + 1;
  }
  return dirs;
}

std::string dirsText(const std::vector<fs::path>& dirs) {
  std::string text;
  for (const auto& dir : dirs)
    text += (text.empty() ? "" : ", ") + quotePath(dir);
  return text.empty() ? "no method folder" : text;
}

// Sets one param as a graph file would, checked against its declaration.
void setParam(Graph& graph, const NodeRegistry& registry, const std::string& node,
              const std::string& param, const ParamValue& value) {
  GraphNode& entry = graph.nodes.at(node);
  const NodeType* type = registry.find(entry.type);
  const ParamDecl* decl = type ? type->findParam(param) : nullptr;
  if (!decl)
    throw GraphError(graph.file, node, "param " + quoteText(param),
                     "the method's node has no such parameter");
  try {
    entry.params[param] = coerceParam(*decl, value);
  } catch (const std::invalid_argument& e) {
    throw GraphError(graph.file, node, "param " + quoteText(param), e.what());
  }
}

void removeNode(Graph& graph, const std::string& node) {
  graph.nodes.erase(node);
  graph.ui.erase(node);
  std::erase_if(graph.connections,
                [&](const Connection& c) { return c.from.node == node || c.to.node == node; });
}

Vec3 toVec3(const Eigen::Vector3d& p) {
  return {p.x(), p.y(), p.z()};
}

}  // namespace

fs::path defaultCloneOutput(const CloneSpec& spec) {
  return spec.source.stem().string() + "_on_" + spec.target.stem().string() + ".obj";
}

std::vector<fs::path> defaultMethodDirs() {
  std::vector<fs::path> dirs = splitPathList(std::getenv("GEOBRUSH_METHOD_PATH"));
  if (const fs::path lib = coreLibraryDir(); !lib.empty())
    dirs.push_back(
        (lib / GEOBRUSH_DATADIR_FROM_LIBDIR / "geobrush" / "methods").lexically_normal());
  return dirs;
}

std::vector<CloneMethod> findMethods(const std::vector<fs::path>& dirs) {
  std::vector<CloneMethod> methods;
  std::set<std::string> names;
  for (const auto& dir : dirs) {
    std::error_code ec;
    std::vector<fs::path> files;
    for (const auto& entry : fs::directory_iterator(dir, ec))
      if (entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files)
      if (names.insert(file.stem().string()).second)
        methods.push_back({file.stem().string(), file});
  }
  return methods;
}

Graph readMethod(const std::string& name, const std::vector<fs::path>& dirs,
                 const NodeRegistry& registry) {
  const auto methods = findMethods(dirs);
  const auto method = std::find_if(methods.begin(), methods.end(),
                                   [&](const CloneMethod& m) { return m.name == name; });
  if (method == methods.end()) {
    std::string known;
    for (const auto& m : methods)
      known += (known.empty() ? "" : ", ") + m.name;
    throw GraphError({}, "", "",
                     "no clone method " + quoteText(name) + " (methods: " +
                         (known.empty() ? "none" : known) + "; searched " + dirsText(dirs) + ")");
  }
  Graph graph = readGraphFile(method->file);
  prepareGraph(graph, registry);
  for (const char* role : kRoleNodes)
    if (!graph.nodes.contains(role))
      throw GraphError(graph.file, role, "", "a clone method needs a node of this name");
  return graph;
}

void fillCloneGraph(Graph& graph, const NodeRegistry& registry, const CloneSpec& spec,
                    const CloneOutputs& outputs, const std::optional<CloneView>& view) {
  const auto absolute = [](const fs::path& path) { return fs::absolute(path).lexically_normal(); };
  setParam(graph, registry, "source_mesh", "path", absolute(spec.source).string());
  setParam(graph, registry, "target_mesh", "path", absolute(spec.target).string());

  if (!(spec.radius > 0))
    throw GraphError(graph.file, "strokes", "param 'dabs'",
                     "the region's radius must be positive, got " + formatParam(spec.radius));
  const double canvasRadius = spec.radius * (1 + kCloneCanvasMargin);
  const Vec3& p = spec.sourcePoint;
  setParam(graph, registry, "source_canvas", "origin", p);
  setParam(graph, registry, "source_canvas", "dabs",
           std::vector<double>{p[0], p[1], p[2], canvasRadius});
  // The shared domain's unit is the source's length: the region is a disc of the radius there.
  setParam(graph, registry, "strokes", "dabs", std::vector<double>{0, 0, spec.radius, 1});

  setParam(graph, registry, "target_map", "origin", spec.targetPoint);
  setParam(graph, registry, "target_map", "scale", spec.scale);
  setParam(graph, registry, "target_map", "angle", spec.angleDeg);

  setParam(graph, registry, "save_result", "path", absolute(outputs.mesh).string());
  if (!graph.nodes.contains("render_result")) return;
  if (outputs.image.empty()) {
    removeNode(graph, "render_result");
    return;
  }
  setParam(graph, registry, "render_result", "path", absolute(outputs.image).string());
  if (!view) return;
  setParam(graph, registry, "render_result", "focus", view->focus);
  setParam(graph, registry, "render_result", "focus_radius", view->radius);
  setParam(graph, registry, "render_result", "azimuth", view->azimuthDeg);
  setParam(graph, registry, "render_result", "elevation", view->elevationDeg);
}

SnappedSpec snapToSurfaces(const CloneSpec& spec, const TriMesh& source, const TriMesh& target) {
  SnappedSpec snapped{spec};
  const auto snap = [](const TriMesh& mesh, Vec3& point) {
    const SurfacePoint nearest =
        nearestSurfacePoint(mesh, Eigen::Vector3d(point[0], point[1], point[2]));
    point = toVec3(nearest.point);
    return nearest.distance;
  };
  snapped.sourceMoved = snap(source, snapped.spec.sourcePoint);
  const SurfacePoint onTarget = nearestSurfacePoint(
      target, Eigen::Vector3d(spec.targetPoint[0], spec.targetPoint[1], spec.targetPoint[2]));
  snapped.spec.targetPoint = toVec3(onTarget.point);
  snapped.targetMoved = onTarget.distance;
  const auto normal = target.calc_face_normal(TriMesh::FaceHandle(onTarget.face));
  if (normal.norm() > 0) snapped.targetNormal = {normal[0], normal[1], normal[2]};
  return snapped;
}

CloneView viewFacing(const Vec3& focus, double pasteRadius, const Vec3& normal) {
  // The paste's extent on the target, and as much again of the target around it.
  constexpr double kFramedRadii = 2.0;
  // Off the normal, so that relief casts shading; the elevation stays short of the poles.
  constexpr double kTurnDeg = 25, kLiftDeg = 20, kHighestDeg = 80;
  const double length =
      std::sqrt(normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]);
  const Vec3 n =
      length > 0 ? Vec3{normal[0] / length, normal[1] / length, normal[2] / length} : Vec3{0, 0, 1};
  const double toDegrees = 180 / M_PI;
  CloneView view;
  view.focus = focus;
  view.radius = kFramedRadii * pasteRadius;
  view.azimuthDeg = std::atan2(n[0], n[2]) * toDegrees + kTurnDeg;
  if (view.azimuthDeg > 180) view.azimuthDeg -= 360;
  view.elevationDeg = std::clamp(std::asin(std::clamp(n[1], -1.0, 1.0)) * toDegrees + kLiftDeg,
                                 -kHighestDeg, kHighestDeg);
  return view;
}

CloneView cloneView(const SnappedSpec& snapped) {
  return viewFacing(snapped.spec.targetPoint, snapped.spec.radius * snapped.spec.scale,
                    snapped.targetNormal);
}

namespace {

void requireMeshFile(const char* option, const fs::path& path) {
  std::error_code ec;
  if (fs::is_regular_file(path, ec)) return;
  throw GraphError({}, "", "",
                   std::string(option) + ": " + quotePath(path) +
                       (fs::exists(path, ec) ? ": not a regular file" : ": no such file"));
}

}  // namespace

Graph startCloneGraph(const CloneRequest& request, const NodeRegistry& registry) {
  requireMeshFile("source", request.spec.source);
  requireMeshFile("target", request.spec.target);
  Graph graph = readMethod(request.method, request.methodDirs, registry);
  fillCloneGraph(graph, registry, request.spec, request.outputs);
  return graph;
}

SnappedSpec finishCloneGraph(Graph& graph, const CloneRequest& request,
                             const NodeRegistry& registry, const Mesh& source, const Mesh& target) {
  const SnappedSpec snapped = snapToSurfaces(request.spec, source.surface, target.surface);
  fillCloneGraph(graph, registry, snapped.spec, request.outputs, cloneView(snapped));
  for (const auto& assignment : request.sets)
    setParamFromText(graph, registry, assignment);
  checkOutputPaths(graph, registry, fs::current_path());
  return snapped;
}

}  // namespace geobrush
