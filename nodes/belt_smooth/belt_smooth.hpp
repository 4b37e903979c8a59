// The belt smoothing of EMD detail transfer (Sec. 3.5, Fig. 4d): the rebuilt region meets the
// untouched surface with a kink (the boundary effect), so the vertices within a few rings of the
// region's border, on both sides, are Laplacian-smoothed with everything else fixed.
#pragma once

#include <cstdint>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

struct BeltSmoothOptions {
  int rings = 2;        // the belt: vertices fewer than this many rings from the border's edges
  int iterations = 3;   // Jacobi passes
  double lambda = 0.5;  // each pass moves a vertex this share of the way to its neighbours' mean
};

struct BeltSmoothResult {
  TriMesh mesh;
  std::vector<int> belt;       // the vertices smoothed, ascending
  std::vector<int> seamFaces;  // faces with corners on both sides of the region's border
};

// `inRegion`: per vertex of `mesh`, 1 in the region. The mesh's own boundary vertices stay put.
// Throws std::invalid_argument when inRegion's length is not the vertex count,
// std::out_of_range for rings outside 1..16, iterations outside 0..1000, lambda outside (0, 1].
BeltSmoothResult smoothBelt(const TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                            const BeltSmoothOptions& options);

// The same in place: `mesh` is smoothed; the result's mesh is left empty.
BeltSmoothResult smoothBeltInPlace(TriMesh& mesh, const std::vector<std::uint8_t>& inRegion,
                                   const BeltSmoothOptions& options);

}  // namespace geobrush
