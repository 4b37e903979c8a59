// An additive draft for GeoBrush (the paper's future work, Sec. 7: keep the target's detail where
// the source's is pasted). In place of the cage warp's G(P_s), each source canvas vertex is put
// at the target's own surface under its (u, v) plus the source's detail there: its offset from
// the source canvas' smooth base, in the base's local frame, carried into the target's frame and
// scaled by the paste's scale. The membrane and the stitch then join it to the target as they
// join a warped draft, so the result is the target surface with the source's detail added.
#pragma once

#include "geobrush/canvas.hpp"

namespace geobrush {

struct AdditiveDraftOptions {
  double gain = 1.0;  // multiplies the source's detail
};

struct AdditiveDraft {
  TriMesh draft;  // the source canvas surface, each vertex moved as above
  TriMesh base;   // the source canvas' smooth base (its harmonic surface over the loop)
  double largestDetail = 0.0;  // the longest source offset from the base, in source units
};

// Throws std::invalid_argument for a source canvas without a boundary loop (nothing to span a
// base over) or a parameterization whose uv count is not its canvas' vertex count.
AdditiveDraft additiveDraft(const Parameterization& source, const Parameterization& target,
                            const AdditiveDraftOptions& options);

}  // namespace geobrush
