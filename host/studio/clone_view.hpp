// What the studio's viewports show of a clone graph: which nodes play the paper's roles (found by
// type and by the ports that join them, so any clone graph works), the values they computed,
// and the source and target surfaces drawn with their canvases' (u, v) lines (paper Fig. 3).
// No widgets here: tests drive it directly.
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/field_colors.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"

namespace geobrush::studio {

// The nodes of one clone. Empty names where a role has no node.
struct CloneRoles {
  std::string roi;           // a geobrush.roi node
  std::string strokes;       // the geobrush.strokes node upstream of the ROI's strokes
  std::string sourceMap;     // feeds roi.source
  std::string targetMap;     // feeds roi.target: the target canvas (a geobrush.dem)
  std::string sourceCanvas;  // the geobrush.canvas_grow feeding the source map's canvas
  Endpoint sourceMesh;       // feeds the canvas's mesh
  Endpoint targetMesh;       // feeds the target map's mesh
  Endpoint roiStrokes;       // feeds roi.strokes (after ROI correction, where there is one)
  // Consumes roi.region and outputs a mesh and its paste map (stitch, variational_paste), or
  // else the first node downstream of the ROI whose mesh and map outputs are both used.
  std::string paste;

  bool found() const { return !roi.empty(); }
  // What a live evaluation asks for: the paste, and the maps where there is none.
  std::vector<std::string> liveTargets() const;
};

// The bounding box of a mesh's vertices (what framing and brush sizes start from).
Eigen::AlignedBox3d boundsOf(const TriMesh& mesh);

// The node types that paint the region of interest (geobrush.roi and its drop-ins) and that paste
// it into the target (stitch and its alternatives): what a clone is found by.
bool isRoiType(const std::string& type);
bool isPasteType(const std::string& type);

// The clone around the ROI node `preferredRoi` if it is one, else the first ROI node by name.
CloneRoles findClone(const Graph& graph, const std::string& preferredRoi = {});

// The values of the roles after an evaluation; null where a node failed or did not run.
struct CloneValues {
  MeshPtr sourceMesh;
  MeshPtr targetMesh;
  CanvasPtr canvas;
  ParameterizationPtr sourceMap;
  ParameterizationPtr targetMap;
  StrokesPtr strokes;
  MeshPtr result;
  PasteMapPtr pasteMap;
};

// Reads the roles' outputs from the evaluator's last evaluation (call on the thread that ran it).
CloneValues fetchClone(const Evaluator& evaluator, const CloneRoles& roles);

// A surface as a viewport shows and paints it: its canvas and the painted region coloured, and
// the (u, v) of every vertex on a canvas (NaN elsewhere), which is where a brush touching the
// surface paints and where the coordinate lines run.
struct ShownSurface {
  MeshPtr mesh;
  std::vector<Eigen::Vector2d> uv;
};

// The source mesh with the source canvas; null mesh without a source mesh.
ShownSurface showSource(const CloneValues& values);
// The pasted result where there is one, else the target mesh, with the target canvas; the
// pasted part carries the source canvas's (u, v), so lines run on through it. Null mesh
// without either.
ShownSurface showTarget(const CloneValues& values);

// A per-vertex field a viewport can colour its surface by: one column of a
// geobrush.VertexFields output of the last evaluation (emd_signal's g, emd's modes, ...).
struct FieldLayer {
  std::string node;
  std::string port;
  std::string column;
  std::shared_ptr<const VertexFields> fields;
  std::string label() const { return node + "." + port + ": " + column; }
};

// Every column of every VertexFields output the evaluator holds for the graph's nodes, in the
// order of the nodes' names and their ports (call on the thread that evaluated).
std::vector<FieldLayer> fieldLayers(const Graph& graph, const NodeRegistry& registry,
                                    const Evaluator& evaluator);

// The surface with its vertices coloured by the layer's field (diverging around zero for a
// signed field), its range in `range`; none when the field has not one value per vertex of it.
std::optional<ShownSurface> colouredBy(const ShownSurface& surface, const FieldLayer& layer,
                                       FieldRange* range);

// The canvases' (u, v) coordinate lines (paper Fig. 3) as segments on the faces, the level sets
// u = k s and v = k s of the piecewise linear uv: sharp at any mesh resolution.
struct CoordinateLines {
  struct Set {
    std::vector<Eigen::Vector3d> ends;     // two per segment
    std::vector<Eigen::Vector3d> normals;  // one per segment: its face's, unit
  };
  Set u, v;
};
CoordinateLines coordinateLines(const ShownSurface& surface, double spacing);
// The spacing both views use: a tenth of the source canvas's extent in the domain (0 without one).
double lineSpacing(const CloneValues& values);

// A point where a ray meets a surface.
struct SurfaceHit {
  int face = -1;
  Eigen::Vector3d point;
  Eigen::Vector3d normal;  // of the face, unit, turned towards the ray's origin
  Eigen::Vector3d barycentric;
  double distance = 0;
};

// The nearest hit of the ray (origin, unit direction) on the mesh, if any. Brute force over the
// faces: a click or a mouse move costs about a millisecond on a 300k-face mesh.
std::optional<SurfaceHit> castRay(const TriMesh& mesh, const Eigen::Vector3d& origin,
                                  const Eigen::Vector3d& direction);

// The (u, v) at a hit, interpolated from the surface's per-vertex uv; none where a corner of the
// face is off the canvas.
std::optional<Eigen::Vector2d> uvAt(const ShownSurface& surface, const SurfaceHit& hit);

// The points of the circle of `radius` around `center` in the parameter domain, carried onto a
// parameterized surface by E^-1 (what shows the brush at corresponding places on both surfaces);
// NaN where the circle leaves the canvas.
std::vector<Eigen::Vector3d> domainCircle(const DomainLocator& locator,
                                          const Eigen::Vector2d& center, double radius,
                                          int segments = 48);

}  // namespace geobrush::studio
