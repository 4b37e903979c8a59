// Joining a pasted feature to the target: the target region removed, the gap between the
// feature's loop and the hole's loop triangulated by the shortest-edge zip in space (Barequet and
// Sharir), then smoothed ring by ring (../papers/topology-free-cut-and-paste.txt, section 5.2).
#pragma once

#include <Eigen/Core>
#include <stdexcept>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

struct GapFillOptions {
  int smoothIterations = 3;  // pass k smooths rings 0..k-1 around the gap
};

// Where both loops lie in the target's domain: the hole's in the region's parameterization, the
// feature's where the transfer placed it. With them the gap is zipped in the domain (its
// triangles kept from turning over there), as GeoBrush's stitch does; without, in space.
struct GapDomain {
  const std::vector<Eigen::Vector2d>* regionUv = nullptr;   // per region canvas vertex
  const std::vector<Eigen::Vector2d>* featureUv = nullptr;  // per feature canvas vertex
};

struct GapFillResult {
  TriMesh mesh;  // the target without the region, the feature, and the gap's faces
  PasteMap map;  // sourceVertex: the feature canvas' vertices
};

// `pasted` has the feature canvas' connectivity (vertex i = feature vertex i). Result vertices
// come in this order: the target's kept vertices (increasing), then the feature's. Throws
// std::invalid_argument when the inputs do not belong together or the zip cannot be joined as a
// manifold.
GapFillResult fillGap(const TriMesh& target, const Canvas& region, const TriMesh& pasted,
                      const Canvas& feature, const GapFillOptions& options = {},
                      const GapDomain& domain = {});

}  // namespace geobrush
