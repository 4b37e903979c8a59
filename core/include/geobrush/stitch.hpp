// Stitching (GeoBrush paper section 4.4, Fig. 6d): the source ROI R_in, each vertex v moved to
// x~(E_s(v)) + G(v), replaces the target faces inside Q (those at a vertex in Q, and those R_in's
// outline passes through), and the gap between the two boundaries is triangulated in the
// parameter domain, so that the result is one manifold mesh whose seam shares vertices.
#pragma once

#include <memory>
#include <stdexcept>
#include <string_view>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/domain_locator.hpp"
#include "geobrush/hash.hpp"
#include "geobrush/region.hpp"
#include "geobrush/submesh.hpp"

namespace geobrush {

class Context;

class StitchError : public std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct StitchOptions {
  // On a target much coarser than the source, the target's edge nearest dQ lies up to one coarse
  // triangle away from R_in's outline, and the strips between the two fan many short patch edges
  // onto few long target edges: slivers whose normals flip. Where the target edges crossing dQ are
  // on average more than this many times as long (in the domain) as R_in's boundary edges, the
  // target faces along dQ are first bisected, on the target surface, until their edges there are
  // about as long as R_in's. 0 never refines. Off by default: the vertices the refinement adds
  // are no target mesh vertex (PasteMap::targetVertex -1), and geobrush.variational_paste, which
  // calls stitchPaste, needs one for every fixed vertex near the paste.
  double seamRefinementRatio = 0;
};

struct StitchResult {
  TriMesh mesh;                     // the whole target with the paste
  std::size_t patchVertices = 0;    // vertices taken from R_in
  std::size_t removedFaces = 0;     // target faces replaced (removed, or cut by the refinement)
  std::size_t refinedVertices = 0;  // vertices of `mesh` the seam refinement added on the target
  std::size_t gapTriangles = 0;     // triangles of the seam strips
  std::size_t seamLoops = 0;        // boundary loops of R_in, each zipped to one of the target
  PasteMap map;                     // the origin of each vertex of `mesh`, and the seam faces
  int firstPatchVertex = 0;         // R_in's vertices are the patchVertices from here
  // Whether `mesh` starts with the base's `outside` part, element for element, with the rest
  // joined to it: what restoreOutside needs.
  bool startsWithOutside = false;
};

// The target mesh outside an open part of its faces, which no paste into a canvas within the open
// part changes: each result starts as a copy of `mesh`, and the open faces that stay are joined
// to it.
struct StitchOutside {
  std::vector<int> openMeshFaces;  // the target mesh faces of the open part, increasing
  TriMesh mesh;                    // the target mesh's faces outside the open part
  std::vector<int> meshVertex;     // vertex of `mesh` -> target mesh vertex, increasing
  // The entries of `mesh` that a paste changes when it joins faces to it: its vertices that are
  // corners of open faces too, and every halfedge at one of them.
  std::vector<int> borderVertices, borderHalfedges;
  // The open faces with every face that shares a corner with one, as a mesh of their own whose
  // halfedges keep the target mesh's sides: a paste cuts the target and joins the kept open faces
  // to `mesh` here, with arrays the size of the open part rather than of the target.
  TriMesh local;
  std::vector<int> localVertexToMesh;  // local vertex -> target mesh vertex, increasing
  std::vector<int> localFaceToMesh;    // local face -> target mesh face, increasing
  std::vector<int> localOpenFaces;     // the local faces of the open part, increasing
  // Local vertex, edge and face -> the same element of `mesh`, or -1 where only the open part
  // has it (joinFaces' account of `mesh` for faces of `local`).
  AppendedFaces localInMesh;
};
// The outside of the faces marked in `open` (one flag per face of `targetMesh`).
StitchOutside stitchOutside(const TriMesh& targetMesh, const std::vector<char>& open);

// A region of space around a canvas' origin whose faces make an open part that holds the canvas
// wherever in a cell of space its origin lies, so that the pastes of a drag within the cell share
// one outside (derivedStitchBase). R bounds the canvas vertices' distance from the origin,
// rounded up to a power of 2^(1/4); the cells are cubes of side R / 4 on a lattice through the
// coordinate origin; the open part is the faces with every corner within R plus half the cell's
// diagonal of the centre of the origin's cell. Equal keys give equal open parts of one mesh.
struct OpenCell {
  Hash key = 0;  // the cell and R; 0 for a canvas too degenerate to have one (no shared outside)
  Eigen::Vector3d center = Eigen::Vector3d::Zero();
  double radius = 0;
  double side = 0;         // R / 4
  int quarterOctaves = 0;  // R = 2^(quarterOctaves / 4)
};
OpenCell openCellOf(const Canvas& canvas);
// The cell of R = 2^(quarterOctaves / 4) that holds `point`; key 0 where there is none.
OpenCell openCellAt(int quarterOctaves, const Eigen::Vector3d& point);
// The cell beside `cell` across the face that `point`, in `cell`, reaches first moving along
// `direction`, where it is nearer than a fifth of a side that way: the cell a drag whose canvas
// origin moves that way may enter next. Key 0 where no face is that near or `direction` is zero.
OpenCell nextOpenCell(const OpenCell& cell, const Eigen::Vector3d& point,
                      const Eigen::Vector3d& direction);
// Per face of `mesh`: whether it lies in the cell's open part.
std::vector<char> openFaces(const TriMesh& mesh, const OpenCell& cell);

// How the target canvas sits in its mesh, and the outside of an open part that holds the canvas'
// faces.
struct StitchBase {
  std::vector<int> canvasToMesh;      // target canvas vertex -> target mesh vertex
  std::vector<int> meshToCanvas;      // target mesh vertex -> target canvas vertex, or -1
  std::vector<int> canvasFaceToMesh;  // target canvas face -> target mesh face
  // The same maps with outside->local in place of the target mesh.
  std::vector<int> localToCanvas;      // local vertex -> target canvas vertex, or -1
  std::vector<int> canvasFaceToLocal;  // target canvas face -> local face
  // On the target parameterization: which target faces R_in's outline passes through.
  std::shared_ptr<const DomainLocator> locator;
  std::shared_ptr<const StitchOutside> outside;
  OpenCell cell;  // the cell `outside` belongs to; key 0 where it is the canvas' own
};
// Throws StitchError when the canvas does not map onto its mesh. `locator`, a locator on `target`
// (one other nodes share), is made where null. `outside`, where given and its open part holds
// every canvas face, is shared; otherwise the open part is the canvas' faces.
StitchBase stitchBase(const Parameterization& target,
                      std::shared_ptr<const DomainLocator> locator = nullptr,
                      std::shared_ptr<const StitchOutside> outside = nullptr);
// The stitch base of the target parameterization on `port` as derived data, its outside shared by
// every canvas whose origin lies in one OpenCell: a drag builds a new outside only where the
// canvas' origin crosses into another cell. A canvas whose origin moved from an earlier canvas'
// towards a face of its cell, and nears it, has the outside of the cell beyond (nextOpenCell)
// built on a thread of its own, so that the move into that cell finds it made. The nodes that
// paste into a target share it.
std::shared_ptr<const StitchBase> derivedStitchBase(Context& ctx, std::string_view port);

// `draft` is G(P_s): the source canvas surface with its vertices warped (same connectivity).
// `offset` is the membrane x~ on the region's grid, or null to paste G alone (x~ = 0). An empty
// region gives the target mesh unchanged. Throws StitchError when the draft does not match the
// source canvas, the offset is undefined at a vertex of R_in, the region reaches the edge of the
// target canvas, or the two boundaries cannot be paired loop by loop. `base`, when given, must be
// stitchBase(target). Where the seam refinement (see StitchOptions) cannot make a valid seam, the
// paste is made without it.
StitchResult stitchPaste(const Region2D& region, const Parameterization& source,
                         const TriMesh& draft, const Field2D* offset,
                         const Parameterization& target, const StitchBase* base = nullptr,
                         const StitchOptions& options = {});
// The same, building the mesh in `out` (cleared first) and leaving the result's `mesh` empty.
// OpenMesh meshes have no move constructor, so a returned or moved mesh is copied: a node builds
// straight into the mesh of its output value. With `outHoldsOutside`, `out` already holds
// copyOutside(*base) and is not cleared: the copy, most of a dab's memory traffic, can be made
// ahead of time.
StitchResult stitchPasteInto(TriMesh& out, const Region2D& region, const Parameterization& source,
                             const TriMesh& draft, const Field2D* offset,
                             const Parameterization& target, const StitchBase* base = nullptr,
                             bool outHoldsOutside = false, const StitchOptions& options = {});

// The two halves of stitchPasteInto. The paste's connectivity and seam depend on the region, the
// canvases and their parameterizations alone: stitchLayoutInto builds them, with R_in's vertices
// at the source canvas' positions, while the offset membrane is still being solved; placePatch
// then moves each vertex of R_in (map.sourceVertex >= 0, none before firstPatchVertex) to
// x~(E_s(v)) + G(v). Together they give stitchPasteInto's result bit for bit; they throw
// StitchError as it does. The result's map is built in the arrays of `reuse`; with
// `outHoldsOutside`, `reuse` may be the map of any paste that startsWithOutside with this base's
// outside part, and its entries for the outside part are kept as they are: a dab writes the
// map's entries for what it changes, not for the whole target.
StitchResult stitchLayoutInto(TriMesh& out, const Region2D& region, const Parameterization& source,
                              const Parameterization& target, const StitchBase* base = nullptr,
                              bool outHoldsOutside = false, const StitchOptions& options = {},
                              PasteMap reuse = {});
void placePatch(TriMesh& out, const PasteMap& map, const Parameterization& source,
                const TriMesh& draft, const Field2D* offset, int firstPatchVertex = 0);

// A boundary loop of a paste laid out with its gap open: vertices of the result mesh, in the
// order of the boundary halfedges that join them, each with its place in the parameter domain.
struct DomainLoop {
  std::vector<int> vertices;
  std::vector<Eigen::Vector2d> uv;
};

// A paste laid out up to its gap (section 4.4, Fig. 6d, before the gap is triangulated): the kept
// target faces and R_in in one mesh, not joined to each other. Closing the gap with triangles
// between the two kinds of loops, then finishOpenStitch, make it a paste.
struct OpenStitch {
  // The layout so far: gapTriangles 0; `map` maps every vertex so far and has no seam faces.
  StitchResult result;
  std::vector<DomainLoop> targetLoops;  // the outlines of the target's holes (the seam loops)
  std::vector<DomainLoop> patchLoops;   // R_in's outlines, uv from the source parameterization
  int firstPatchVertex = 0;             // R_in's vertices follow the target part's
  int firstGapFace = 0;                 // the faces a closing adds come from here on
  bool refinedSeam = false;             // whether the seam band was refined
};
// stitchLayoutInto up to the gap: R_in's vertices at the source canvas' positions until
// placePatch. Where the refined seam band cannot be made (see StitchOptions) it is laid out
// without it. Throws StitchError as stitchLayoutInto does, except for what only closing finds.
OpenStitch stitchOpenLayoutInto(TriMesh& out, const Region2D& region,
                                const Parameterization& source, const Parameterization& target,
                                const StitchBase* base = nullptr, bool outHoldsOutside = false,
                                const StitchOptions& options = {});
// Closes the gap as stitchLayoutInto does: each of R_in's loops is paired with the target loop
// nearest to it in the domain and the strip between them zipped. Throws StitchError where the
// loops do not pair or a strip folds onto itself.
void zipOpenStitch(TriMesh& out, const OpenStitch& open);
// The paste once its gap is closed in `out`: the faces added since the layout are its seam
// faces, and the vertices added (on neither mesh) map to -1 in both.
StitchResult finishOpenStitch(const TriMesh& out, OpenStitch open);
// Throws StitchError unless `draft` has the source canvas' vertices and faces.
void requireDraftOf(const TriMesh& draft, const Parameterization& source);

// Copies the target's part outside the open part into `out`, with room for the rest of the target
// and a paste from `sourceCanvas`: what every paste into this target starts from.
void copyOutside(const StitchOutside& outside, const TriMesh& targetMesh,
                 const TriMesh& sourceCanvas, TriMesh& out);

// A paste the computing node published on `port` with `outside` as its note
// (Context::outRecyclable), which the framework has retired and nothing else holds, turned back
// into that outside part in place (restoreOutside, its colours dropped): memory for the node's
// next paste into the same outside. Null where there is none.
std::shared_ptr<Mesh> recyclePasteOutside(Context& ctx, std::string_view port,
                                          const std::shared_ptr<const StitchOutside>& outside);

// Turns `out`, a paste into this base whose result startsWithOutside, back into the outside part
// alone, as copyOutside makes it, in place: the paste's elements are dropped and the border
// entries copied back, at a cost that follows the border rather than the mesh, and the arrays
// keep their room. Throws StitchError when `out` is smaller than the outside part.
void restoreOutside(const StitchOutside& outside, TriMesh& out);

}  // namespace geobrush
