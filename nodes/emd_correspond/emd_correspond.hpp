// The correspondence of EMD detail transfer (Sec. 3.3) and the source half of Eq. 4: each target
// vertex v_t in Q_t, mapped into the shared (u, v) domain, takes the k source canvas vertices
// nearest to it there, CP(v_t), and each source mode averaged over them,
// H_k^s(v_t) = (1/k) sum_{v_s in CP(v_t)} h_k^s(v_s).
#pragma once

#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/domain_neighbours.hpp"

namespace geobrush {

struct EmdCorrespondOptions {
  int neighbours = 4;  // k
  // Multiplies every sampled value: 1 / lambda for modes per unit area, whose detail grows
  // steeper as the paste's scale lambda shrinks it (a curvature density scales as 1 / length).
  double factor = 1.0;
};

struct EmdCorrespondence {
  // Per source field, per target mesh vertex: H^s on Q_t, 0 elsewhere.
  std::vector<std::vector<double>> sampled;
  // Per target mesh vertex: the source canvas vertex nearest in the domain on Q_t, -1 elsewhere.
  std::vector<int> nearest;
};

// `targetVertices`: Q_t as target canvas vertices; `sourceFields`: per field, one value per
// vertex of the source canvas' mesh. Throws std::invalid_argument for a field of the wrong length
// or a target vertex the canvas does not have, std::out_of_range for k outside 1..64 or a
// factor that is not finite.
EmdCorrespondence correspondInDomain(const Parameterization& source, const Parameterization& target,
                                     const std::vector<int>& targetVertices,
                                     const std::vector<const std::vector<double>*>& sourceFields,
                                     const EmdCorrespondOptions& options);
// The same with the source canvas' neighbours given (DomainNeighbours of source.uv).
EmdCorrespondence correspondInDomain(const Parameterization& source,
                                     const DomainNeighbours& sourceNeighbours,
                                     const Parameterization& target,
                                     const std::vector<int>& targetVertices,
                                     const std::vector<const std::vector<double>*>& sourceFields,
                                     const EmdCorrespondOptions& options);

// Q_t's correspondence alone, per target vertex in the order given: what correspondInDomain
// writes at each one's mesh vertex (a caller that keeps arrays of the mesh's size writes these).
struct RegionCorrespondence {
  std::vector<int> meshVertices;             // the target mesh vertex of each
  std::vector<int> nearest;                  // the source canvas vertex nearest in the domain
  std::vector<std::vector<double>> sampled;  // per source field, H^s at each
};
RegionCorrespondence correspondRegion(const Parameterization& source,
                                      const DomainNeighbours& sourceNeighbours,
                                      const Parameterization& target,
                                      const std::vector<int>& targetVertices,
                                      const std::vector<const std::vector<double>*>& sourceFields,
                                      const EmdCorrespondOptions& options);

}  // namespace geobrush
