// Quality of a paste, measured on its result mesh: the seam's continuity (C0: one manifold piece
// whose seam shares vertices; C1: the normal jump across the seam next to the target's own
// dihedral angles there), the fidelity of the pasted detail to the source, and the
// self-intersections the paste made. What `geobrush compare` sets side by side.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/intersection.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

struct PasteMetricsOptions {
  // Pasted vertices closer than this many edges to the seam are left out of the detail measure:
  // the membrane is meant to bend them.
  int seamBand = 3;
  // Faces closer than this fraction of the result's bounding-box diagonal count as touching; also
  // the distance within which two vertices count as one.
  double touchTolerance = 1e-9;
};

struct PasteMetrics {
  std::map<std::string, double> values;  // named as in the node's documentation
  std::vector<std::string> notes;        // what could not be measured, and why
};

// `map` describes `result` (stitch's or another paste node's PasteMap); `target` is the mesh
// pasted into and `source` the source canvas, each optional: what needs a missing input is
// skipped with a note. Throws std::invalid_argument when the map does not match the meshes.
PasteMetrics measurePaste(const TriMesh& result, const PasteMap* map, const TriMesh* target,
                          const TriMesh* source, const PasteMetricsOptions& options = {});

// Against a reference surface, e.g. the patch a hole case removed (the ground truth of a fill):
// each new vertex (one the map ties to no target vertex) measured to the reference's nearest
// point, distances over the result's bounding-box diagonal, and the angle between the result's
// vertex normal there and the reference face's normal; and the other way, each reference vertex
// to the result's nearest point. Adds reference_mean_distance, reference_max_distance,
// reference_normal_mean_deg, reference_vertices, reference_to_result_mean_distance and
// reference_to_result_max_distance to `metrics` (a note where there is no new vertex). The
// reference must have a face.
void measureAgainstReference(const TriMesh& result, const PasteMap& map, const TriMesh& reference,
                             PasteMetrics& metrics);

// Why a measured paste is not a valid result, or nothing: a result that is not manifold, has
// more boundary loops than the target (a seam left open) or new self-intersections.
std::optional<std::string> invalidPaste(const PasteMetrics& metrics);

// The angle in radians between the normals of the two faces of each interior edge listed.
std::vector<double> normalJumps(const TriMesh& mesh, const std::vector<int>& edges);

}  // namespace geobrush
