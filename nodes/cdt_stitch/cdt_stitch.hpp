// The gap between the pasted and the kept parts triangulated as a conforming constrained Delaunay
// triangulation with a minimum angle and a maximum area (GPU texture cloning paper, 3D retrieval:
// "vertices and segments on the boundary are collected and triangulated to meet constraints on
// the minimum angle and maximum triangle area"), in place of geobrush.stitch's zipped strips.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/region.hpp"
#include "geobrush/stitch.hpp"

namespace geobrush {

struct CdtStitchOptions {
  // The smallest interior angle a gap triangle may have, where the outlines allow it (see
  // closeGapByCdt). CGAL's mesher is proven to end up to about 20.7 degrees.
  double minAngleDegrees = 20;
  // The largest area a gap triangle may have in the domain; 0: (sqrt 3 / 4) e^2, e the mean
  // length of the outlines' edges in the domain.
  double maxArea = 0;
  // Let the refinement split the outlines' edges where they are encroached (Ruppert's full
  // algorithm: the bounds then hold on every triangle, but near a corner of the gap sharper than
  // about 60 degrees), each split also splitting the kept target face or the patch face beside
  // it. Off: the outlines keep their edges (Triangle's -Y).
  bool splitBoundary = false;
};

// An input the gap cannot be triangulated from. `port()` names the node input it comes from.
class CdtStitchError : public std::runtime_error {
 public:
  CdtStitchError(std::string port, const std::string& message)
      : std::runtime_error(message), port_(std::move(port)) {}
  const std::string& port() const { return port_; }

 private:
  std::string port_;
};

struct CdtGap {
  std::size_t steinerVertices = 0;  // vertices added inside the gap
  std::size_t outlineVertices = 0;  // vertices added on the outlines (splitBoundary)
  bool targetFacesSplit = false;    // whether a kept target face was split with its outline edge
  std::size_t triangles = 0;        // gap triangles
  std::vector<int> faces;           // the gap triangles' faces in the result mesh
  double maxArea = 0;               // the area bound used (the option, or its default)
};

// Triangulates the gap of `open`, laid out in `out` with R_in already placed (placePatch), as a
// constrained Delaunay triangulation in the domain: the outlines of the target's holes and R_in's
// outlines are its constraints, and the gap is the part of the plane an odd number of outlines
// encloses (between a hole's outline and R_in's, between R_in's inner outline and an island of
// the target). CGAL's Delaunay refinement (Ruppert, Chew) then inserts Steiner points at the
// circumcentres of triangles with an angle below the bound or an edge longer than the side of
// the equilateral triangle of area maxArea. Without splitBoundary no point goes on an outline
// (no edge refinement, like Triangle's -Y): the seam keeps the kept faces' and R_in's edges as
// they are, and a triangle whose circumcentre lies outside the gap or inside the diametral circle
// of an outline edge is left as it is: the bounds hold wherever the outlines allow. With it, an
// encroached outline edge is split at its midpoint, in `out` too (see CdtStitchOptions). A
// Steiner point w goes to X_T(w) + h(w): the target surface there, plus an offset harmonic on the
// gap triangulation (cotangent weights in the domain) that is each R_in outline vertex's placed
// position minus X_T at its uv on R_in's outlines and 0 on the target's. Throws
// CdtStitchError("region") where outlines cross or touch or the gap cannot be oriented,
// CdtStitchError("min_angle_deg"/"max_area") for bounds out of range or that would not end.
CdtGap closeGapByCdt(TriMesh& out, const OpenStitch& open, const DomainLocator& targetLocator,
                     const CdtStitchOptions& options = {});

struct CdtStitchResult {
  StitchResult paste;  // the paste; its gapTriangles are the gap's triangles
  CdtGap gap;
};

// The whole paste into `out` (cleared first): the layout of geobrush.stitch with its gap left
// open (no seam refinement), R_in placed at x~(E_s(v)) + G(v), the gap closed by closeGapByCdt.
// `base`, when given, must be stitchBase(target). With `outHoldsOutside`, `out` already holds the
// base's outside part (restoreOutside turns a result that startsWithOutside back into it) and is
// not cleared. Throws CdtStitchError naming the input at fault.
CdtStitchResult cdtStitchPasteInto(TriMesh& out, const Region2D& region,
                                   const Parameterization& source, const TriMesh& draft,
                                   const Field2D* offset, const Parameterization& target,
                                   const StitchBase* base = nullptr,
                                   const CdtStitchOptions& options = {},
                                   bool outHoldsOutside = false);

}  // namespace geobrush
