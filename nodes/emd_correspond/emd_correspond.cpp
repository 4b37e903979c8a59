#include "emd_correspond.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

#include "geobrush/domain_neighbours.hpp"
#include "geobrush/parallel.hpp"

namespace geobrush {

EmdCorrespondence correspondInDomain(const Parameterization& source, const Parameterization& target,
                                     const std::vector<int>& targetVertices,
                                     const std::vector<const std::vector<double>*>& sourceFields,
                                     const EmdCorrespondOptions& options) {
  if (source.uv.empty()) throw std::invalid_argument("the source canvas has no vertices");
  return correspondInDomain(source, DomainNeighbours(source.uv), target, targetVertices,
                            sourceFields, options);
}

EmdCorrespondence correspondInDomain(const Parameterization& source,
                                     const DomainNeighbours& neighbours,
                                     const Parameterization& target,
                                     const std::vector<int>& targetVertices,
                                     const std::vector<const std::vector<double>*>& sourceFields,
                                     const EmdCorrespondOptions& options) {
  RegionCorrespondence region =
      correspondRegion(source, neighbours, target, targetVertices, sourceFields, options);
  const std::size_t targetMeshSize = target.canvas->source->surface.n_vertices();
  EmdCorrespondence result;
  result.sampled.assign(sourceFields.size(), std::vector<double>(targetMeshSize, 0.0));
  result.nearest.assign(targetMeshSize, -1);
  for (std::size_t i = 0; i < region.meshVertices.size(); ++i) {
    const std::size_t v = std::size_t(region.meshVertices[i]);
    result.nearest[v] = region.nearest[i];
    for (std::size_t k = 0; k < sourceFields.size(); ++k)
      result.sampled[k][v] = region.sampled[k][i];
  }
  return result;
}

RegionCorrespondence correspondRegion(const Parameterization& source,
                                      const DomainNeighbours& neighbours,
                                      const Parameterization& target,
                                      const std::vector<int>& targetVertices,
                                      const std::vector<const std::vector<double>*>& sourceFields,
                                      const EmdCorrespondOptions& options) {
  if (options.neighbours < 1 || options.neighbours > 64)
    throw std::out_of_range("neighbours must be in 1..64");
  if (!std::isfinite(options.factor)) throw std::out_of_range("the factor is not finite");
  if (source.uv.empty() || neighbours.size() != source.uv.size())
    throw std::invalid_argument("the source canvas has no vertices, or other ones than searched");
  const std::vector<int>& sourceMeshVertex = source.canvas->sourceVertex;
  const std::size_t sourceMeshSize = source.canvas->source->surface.n_vertices();
  for (const auto* field : sourceFields)
    if (field->size() != sourceMeshSize)
      throw std::invalid_argument("a source field has " + std::to_string(field->size()) +
                                  " values for " + std::to_string(sourceMeshSize) + " vertices");
  for (int t : targetVertices)
    if (t < 0 || std::size_t(t) >= target.uv.size())
      throw std::invalid_argument("target canvas vertex " + std::to_string(t) + " is not there");
  const std::size_t n = targetVertices.size();
  RegionCorrespondence result;
  result.meshVertices.resize(n);
  result.nearest.resize(n);
  result.sampled.assign(sourceFields.size(), std::vector<double>(n));
  // Each target vertex reads the tree and writes its own entries: the blocks run on any number of
  // threads with the same result.
  parallelBlocks(n, 1024, 0, [&](std::size_t first, std::size_t last) {
    for (std::size_t i = first; i < last; ++i) {
      const std::size_t t = std::size_t(targetVertices[i]);
      const std::vector<int> near = neighbours.nearest(target.uv[t], options.neighbours);
      result.meshVertices[i] = target.canvas->sourceVertex[t];
      result.nearest[i] = near.front();
      for (std::size_t k = 0; k < sourceFields.size(); ++k) {
        double sum = 0.0;
        for (int s : near)
          sum += (*sourceFields[k])[std::size_t(sourceMeshVertex[std::size_t(s)])];
        result.sampled[k][i] = options.factor * sum / double(near.size());
      }
    }
  });
  return result;
}

}  // namespace geobrush
