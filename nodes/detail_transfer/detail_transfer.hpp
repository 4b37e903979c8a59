// Forward mapping of an encoded feature onto a target base (../papers/topology-free-cut-and-
// paste.txt, section 5: the source base is laid onto the target base through the common domain,
// then each feature vertex is rebuilt over its moved base face).
#pragma once

#include <Eigen/Geometry>
#include <stdexcept>

#include "geobrush/cut_paste.hpp"

namespace geobrush {

struct DetailTransferOptions {
  // The source base is shrunk about the walked loop's centre by this factor at a time until the
  // target base covers it.
  double shrinkStep = 0.99;
  int maxShrinks = 200;
};

struct DetailTransferResult {
  TriMesh pasted;  // F's connectivity, its vertices rebuilt over the target base
  // Each feature vertex's place in the target's domain: its source domain point, aligned (what
  // the gap between the pasted outline and the hole is laid out in).
  std::vector<Eigen::Vector2d> placedUv;
  // The similarity from the source base's domain to the target's (Umeyama, from the base's
  // loop to the walked loop's domain points), after shrinking.
  Eigen::Matrix3d alignment = Eigen::Matrix3d::Identity();
  double shrink = 1;             // the factor applied to cover
  double alignmentResidual = 0;  // RMS distance in the target's domain before shrinking
  std::size_t uncovered = 0;     // source base vertices still outside the target base
  // Pairs of the pasted feature's faces that meet, beyond those the feature had at its source:
  // where the target bends against the feature (a convex feature pasted into a concave region,
  // the paper's admitted failure) its offsets cross.
  std::size_t newSelfIntersections = 0;
};

// Step 1: each source base vertex's domain point, aligned, is looked up on the target base;
// step 2: each feature vertex = its barycentric point on the moved face plus scale times its
// offset in that face's frame. `walk` holds one target point per vertex of the source base's
// boundary loop (geobrush.geodesic_region). Throws std::invalid_argument when the inputs do not
// belong together.
DetailTransferResult transferDetail(const DetailEncoding& encoding,
                                    const Parameterization& targetFeature,
                                    const Parameterization& targetBase, const SurfacePath& walk,
                                    const DetailTransferOptions& options = {});

}  // namespace geobrush
