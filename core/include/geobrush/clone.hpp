// One clone specified once, and the method templates that turn it into a graph (DESIGN.md,
// "Alternatives: one clone spec, many methods").
//
// A method is a graph file in a method folder (graphs/methods/<name>.json in the source tree,
// <prefix>/share/geobrush/methods when installed). It names its nodes by role, and a clone fills
// their params:
//   source_mesh    (path)         the mesh the detail comes from
//   source_canvas  (canvas_grow)  origin and one dab around the region, with a margin
//   target_mesh    (path)         the mesh it is pasted onto
//   target_map     (dem)          origin, scale and angle of the paste
//   strokes        (strokes)      one dab of the region's radius at the domain's origin
//   save_result    (save_mesh)    the result mesh's path
//   render_result  (render)       the picture's path; removed when no picture is asked for
// Every other node of the method keeps the params its file gives.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "geobrush/graph.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

struct CloneSpec {
  std::filesystem::path source;
  Vec3 sourcePoint{};  // the centre of the region on the source mesh
  double radius = 0;   // of the region: geodesic, in the source mesh's units
  std::filesystem::path target;
  Vec3 targetPoint{};  // where the region's centre lands on the target mesh
  double scale = 1;    // the target size of the detail over its source size
  double angleDeg = 0;
};

struct CloneOutputs {
  std::filesystem::path mesh;
  std::filesystem::path image;  // empty: no picture
};

// Where a clone writes its mesh when no path is given: SOURCE_on_TARGET.obj in the working folder.
std::filesystem::path defaultCloneOutput(const CloneSpec& spec);

// The source canvas reaches this fraction of the radius beyond the region: room for the
// membrane's two fixed rings of grid nodes, the cage around the canvas and the region's correction
// (paper section 4.5), which may take in a little more than the painted disc. A feature that the
// correction takes in whole far beyond the disc (a lacing of handles) needs a larger canvas:
// --set source_canvas.dabs=X,Y,Z,RADIUS.
inline constexpr double kCloneCanvasMargin = 1.0;

// Folders searched for methods, in order: GEOBRUSH_METHOD_PATH (colon-separated), then
// <prefix>/share/geobrush/methods of the installation holding the core library (the build tree
// mirrors it).
std::vector<std::filesystem::path> defaultMethodDirs();

struct CloneMethod {
  std::string name;  // the file's stem
  std::filesystem::path file;
};
// Every method found, by name; a name found twice is the first folder's.
std::vector<CloneMethod> findMethods(const std::vector<std::filesystem::path>& dirs);

// A method's template, read and prepared against the registry. Throws GraphError naming the
// method and the folders searched when there is none, or the file when it lacks a role node.
Graph readMethod(const std::string& name, const std::vector<std::filesystem::path>& dirs,
                 const NodeRegistry& registry);

// How the picture of a clone frames the paste: the ball around the target point that holds it
// and some target around it, seen from outside the surface there, a little from the side and
// above so that relief shows.
struct CloneView {
  Vec3 focus{};
  double radius = 0;
  double azimuthDeg = 0;
  double elevationDeg = 0;
};

// Sets the role nodes' params from the spec (paths made absolute, so the graph runs from
// anywhere), and the picture's view where one is given and the method renders. Throws GraphError
// naming the node and param for a value out of its range (e.g. a radius that is not positive).
void fillCloneGraph(Graph& graph, const NodeRegistry& registry, const CloneSpec& spec,
                    const CloneOutputs& outputs, const std::optional<CloneView>& view = {});

// The spec with each point moved to the nearest point of its mesh, how far each moved, and the
// target's normal there (of the face the point lies on).
struct SnappedSpec {
  CloneSpec spec;
  double sourceMoved = 0;
  double targetMoved = 0;
  Vec3 targetNormal{0, 0, 1};
};
SnappedSpec snapToSurfaces(const CloneSpec& spec, const TriMesh& source, const TriMesh& target);

// The view of a paste of radius `pasteRadius` around `focus` on a surface with this normal there:
// the paste and as much again around it, seen from outside.
CloneView viewFacing(const Vec3& focus, double pasteRadius, const Vec3& normal);
// The view that frames the paste of a snapped spec.
CloneView cloneView(const SnappedSpec& snapped);

// A clone as `geobrush clone` and the Python module's clone() take it.
struct CloneRequest {
  CloneSpec spec;
  std::string method = "geobrush";
  std::vector<std::string> sets;  // NODE.PARAM=VALUE, applied to the filled method
  CloneOutputs outputs;
  std::vector<std::filesystem::path> methodDirs = defaultMethodDirs();
};

// The two stages of turning a request into a graph, around the loading of its meshes: evaluate
// the started graph's kCloneMeshNodes (through the evaluator that then runs the whole clone, so
// that the meshes are read once), then finish it.
inline constexpr const char* kCloneMeshNodes[] = {"source_mesh", "target_mesh"};

// The request's method filled with its spec as given. Throws GraphError for a mesh that is not a
// regular file (naming the option, "source" or "target"), an unknown method or a value out of
// its range.
Graph startCloneGraph(const CloneRequest& request, const NodeRegistry& registry);

// Snaps the spec's points to the loaded meshes, fills the graph again with the snapped spec and
// the view that frames the paste, applies the request's assignments and checks that no two
// outputs name one file. Throws GraphError.
SnappedSpec finishCloneGraph(Graph& graph, const CloneRequest& request,
                             const NodeRegistry& registry, const Mesh& source, const Mesh& target);

}  // namespace geobrush
