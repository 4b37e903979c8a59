// The offset membrane's data on the region's grid (GeoBrush paper section 4.4, Eqs. 4-5): outside
// Q the membrane must carry the draft onto the target, so a node u there gets
// R_out(u) - g_in(u) = E_t^-1(u) - G(E_s^-1(u)).
#pragma once

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

// `draft` is G(P_s) (the source canvas' connectivity); the locators are on `source` and `target`.
// Throws std::invalid_argument when the draft does not match the source canvas.
MembraneSetup membraneSetup(const Region2D& region, const Parameterization& source,
                            const TriMesh& draft, const DomainLocator& sourceLocator,
                            const DomainLocator& targetLocator, MembraneContinuity continuity);

// The solved membrane as a field: solution values where `setup.defined`, zero elsewhere.
Field2D membraneField(const Region2D& region, const MembraneSetup& setup,
                      const std::vector<std::vector<double>>& values);

}  // namespace geobrush
