// Features and their bases by the cut-and-paste pipeline's convention (cut_paste.hpp), for the
// suites of its nodes.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "geobrush/canvas.hpp"

namespace geobrush::test {

// The canvas of `faces` of `mesh`, its origin at the centre of the lowest face.
CanvasPtr canvasOf(const MeshPtr& mesh, std::vector<int> faces);

// A base over F's boundary loop: the loop's vertices, a split point at the middle of each edge
// i -> i + 1 with i in `split`, then the loop's centroid joined to all.
MeshPtr centroidFan(const Canvas& feature, const std::vector<int>& split = {});

// F's own triangles as a base: its boundary vertices first, in F.boundary's order, then the
// others, smoothed `iterations` times with the boundary fixed; then each boundary edge i -> i + 1
// with i in `split` split at its midpoint, the new vertices last.
MeshPtr membraneBase(const Canvas& feature, int iterations, const std::vector<int>& split = {});

// The face whose centroid is nearest to p (ties: the lowest).
int nearestFace(const TriMesh& mesh, const Eigen::Vector3d& p);

}  // namespace geobrush::test
