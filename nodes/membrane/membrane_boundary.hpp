// The offset membrane's data on the region's grid (GeoBrush paper section 4.4, Eqs. 4-5): outside
// Q the membrane must carry the draft onto the target, so a node u there gets
// R_out(u) - g_in(u) = E_t^-1(u) - G(E_s^-1(u)).
#pragma once

#include <algorithm>
#include <vector>

#include "geobrush/domain_locator.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/region.hpp"
#include "membrane.hpp"

namespace geobrush {

struct MembraneSetup {
  MembraneProblem problem;  // three channels (x, y, z) holding the data at the fixed nodes
  // Nodes the output field defines: the unknowns, the fixed nodes, and the corners of every grid
  // cell that holds a vertex of R_in (the stitch samples the field there).
  std::vector<std::uint8_t> defined;
};

// What the locators answered at the grid's nodes: E_t^-1(u) and the source canvas face and
// barycentric coordinates of u. They depend on the canvases and the grid alone, which stay the
// same while a stroke is painted, so a brush keeps them from dab to dab and each dab locates only
// the nodes it newly samples. Whoever keeps one clears what a canvas change makes stale (a drag
// of the target canvas leaves the source's answers valid); a change of grid clears it by itself.
struct MembraneLocations {
  DomainGrid grid;
  std::vector<std::uint8_t> sourceKnown, targetKnown;  // per node
  std::vector<Eigen::Vector3d> targetPoint;
  std::vector<int> sourceFace;
  std::vector<Eigen::Vector3d> sourceBarycentric;
  void clear() {
    sourceKnown.clear();
    targetKnown.clear();
  }
  void clearTarget() { std::fill(targetKnown.begin(), targetKnown.end(), 0); }
};

// `draft` is G(P_s) (the source canvas' connectivity); the locators are on `source` and `target`;
// `locations`, when given, holds their answers from earlier calls on the same canvases.
// Throws std::invalid_argument when the draft does not match the source canvas.
MembraneSetup membraneSetup(const Region2D& region, const Parameterization& source,
                            const TriMesh& draft, const DomainLocator& sourceLocator,
                            const DomainLocator& targetLocator, MembraneContinuity continuity,
                            MembraneLocations* locations = nullptr);

// The solved membrane as a field: solution values where `setup.defined`, zero elsewhere.
Field2D membraneField(const Region2D& region, const MembraneSetup& setup,
                      const std::vector<std::vector<double>>& values);

}  // namespace geobrush
