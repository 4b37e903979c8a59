// Automatic ROI correction (GeoBrush paper section 4.5, Fig. 9): the outline of Q must not cut
// through faces that the source map folds over (they have no one-to-one image to stitch along).
// Flagged faces crossed by the outline are grown through adjacent flagged faces, and a region
// slightly larger than their image is added to Q. With protrusions included, faces that merely
// turn steeply away from the DEM normal are flagged too, so painting part of a spike takes all of
// it.
#pragma once

#include <stdexcept>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

class RoiCorrectError : public std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

struct RoiCorrectOptions {
  // Off: the parameterization's reversed flags are used as they are. On: faces whose unit normal
  // . DEM normal is below protrusionThreshold are flagged, grown by `ring` rings (k = 3 in the
  // paper).
  bool includeProtrusions = false;
  double protrusionThreshold = 0.5;
  int ring = 3;
  // Each added disc reaches this fraction of its radius beyond the flagged faces' image.
  double margin = 0.1;
  // Adding a disc can cut other flagged faces; corrections repeat at most this often.
  int maxRounds = 8;
};

struct RoiCorrectResult {
  Strokes strokes;                // the input dabs, then one added dab per corrected feature
  std::vector<int> addedFaces;    // F_r: the flagged faces the added dabs take in, ascending
  std::size_t featuresAdded = 0;  // components of F_r
  bool settled = true;            // false when maxRounds were not enough to leave no cut
  // Added faces at the canvas' outline: the region then ends at the outline inside folded
  // geometry, and the seam there may fold (grow the canvas to take the whole feature). Ascending.
  std::vector<int> outlineFaces;
};

// The canvas faces the correction may take in, per face 1 or 0: they depend on the source and the
// options only, so a brush computes them once and passes them to each dab's correction.
std::vector<std::uint8_t> correctionFlags(const Parameterization& source,
                                          const RoiCorrectOptions& options = {});

// Throws RoiCorrectError when the parameterization has no canvas or flags of the wrong size, or
// an option is out of range.
RoiCorrectResult correctRoi(const Strokes& strokes, const Parameterization& source,
                            const RoiCorrectOptions& options = {});
// The same with the flags computed before (correctionFlags of the same source and options).
RoiCorrectResult correctRoi(const Strokes& strokes, const Parameterization& source,
                            const RoiCorrectOptions& options,
                            const std::vector<std::uint8_t>& flagged);

}  // namespace geobrush
