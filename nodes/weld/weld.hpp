// Joining a repair patch to the holed mesh it fills: patch boundary vertices on the hole's border
// become the border's vertices, and the gaps left between the two loops are zipped
// (Freeform surface inpainting, Fig. 2 stage 8).
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

struct WeldOptions {
  // Patch boundary vertices this close to a border vertex (relative to the holed mesh's bounding
  // diagonal) become that vertex.
  double shareTolerance = 1e-6;
};

struct WeldResult {
  // The holed mesh's vertices and faces in their order (then the vertices and faces that split
  // border edges), then the patch's vertices that are not shared and its faces, then the strip
  // faces zipped into the gaps.
  TriMesh mesh;
  // targetVertex: the holed mesh's vertices; sourceVertex: the patch's (shared vertices have
  // both); seamFaces: the strip faces and the patch faces on a shared seam edge.
  PasteMap map;
  std::size_t sharedVertices = 0;
  std::size_t stripFaces = 0;
  // Border edges split where a patch boundary vertex lies on one (the new border vertex follows
  // the holed mesh's; the map ties it to neither input).
  std::size_t borderSplits = 0;
  // Patch boundary edges split at an ear of the holed mesh (a border vertex whose neighbours the
  // holed mesh joins by an edge), so that the patch runs around it.
  std::size_t earSplits = 0;
  // Patch faces removed where they still overlapped the holed mesh at the border (seen along the
  // holed faces' normals), and patch vertices the removal put on the patch's boundary that were
  // moved onto a border vertex it left unshared.
  std::size_t trimmedFaces = 0, snappedVertices = 0;
  bool patchFlipped = false;  // the patch came oriented along the hole and was turned over
};

// A refusal, naming the input at fault ("border" or "patch").
class WeldError : public std::invalid_argument {
 public:
  WeldError(std::string port, const std::string& message)
      : std::invalid_argument(message), port_(std::move(port)) {}
  const std::string& port() const { return port_; }

 private:
  std::string port_;
};

// Welds `patch` (a mesh with exactly one boundary loop) into the hole of `holed` bounded by
// `border` (a boundary loop of `holed`, in the direction of its boundary halfedges). Shared
// vertices must keep both loops' cyclic order. Throws WeldError when an input does not fit, or the
// result would not be a manifold, consistently oriented mesh or would have faces at the seam that
// meet others beyond their shared corners.
WeldResult weld(const TriMesh& holed, const std::vector<int>& border, const TriMesh& patch,
                const WeldOptions& options = {});

}  // namespace geobrush
