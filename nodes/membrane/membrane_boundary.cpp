#include "membrane_boundary.hpp"

#include <cmath>
#include <stdexcept>

namespace geobrush {
namespace {

Eigen::Vector3d draftPoint(const TriMesh& draft, const TriMesh& canvas, int face,
                           const Eigen::Vector3d& barycentric) {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto v : canvas.fv_range(TriMesh::FaceHandle(face))) {
    const auto& p = draft.point(v);
    point += barycentric[k++] * Eigen::Vector3d(p[0], p[1], p[2]);
  }
  return point;
}

}  // namespace

MembraneSetup membraneSetup(const Region2D& region, const Parameterization& source,
                            const TriMesh& draft, const DomainLocator& sourceLocator,
                            const DomainLocator& targetLocator, MembraneContinuity continuity,
                            MembraneLocations* locations) {
  const TriMesh& canvas = source.canvas->surface;
  if (draft.n_vertices() != canvas.n_vertices() || draft.n_faces() != canvas.n_faces())
    throw std::invalid_argument("the draft does not have the source canvas' vertices and faces");
  const DomainGrid& grid = region.grid;
  MembraneSetup setup;
  MembraneProblem& problem = setup.problem;
  problem.width = grid.width;
  problem.height = grid.height;
  problem.inside = region.inside;
  problem.continuity = continuity;
  problem.channels.assign(3, std::vector<double>(grid.nodeCount(), 0.0));
  const std::vector<MembraneNode> roles =
      classifyMembraneNodes(grid.width, grid.height, region.inside, continuity);

  setup.defined.assign(grid.nodeCount(), 0);
  std::vector<std::uint8_t> sampled(grid.nodeCount(), 0);
  for (std::size_t n = 0; n < roles.size(); ++n) {
    setup.defined[n] = roles[n] != MembraneNode::Unused;
    sampled[n] = roles[n] == MembraneNode::Fixed;
  }
  for (int v : region.sourceVertices) {
    const Eigen::Vector2d g = (source.uv[std::size_t(v)] - grid.origin) / grid.spacing;
    const int i = int(std::floor(g.x())), j = int(std::floor(g.y()));
    for (int dj = 0; dj <= 1; ++dj)
      for (int di = 0; di <= 1; ++di) {
        if (i + di < 0 || j + dj < 0 || i + di >= grid.width || j + dj >= grid.height) continue;
        const std::size_t n = grid.index(i + di, j + dj);
        if (!setup.defined[n]) sampled[n] = setup.defined[n] = 1;
      }
  }
  MembraneLocations local;
  MembraneLocations& located = locations ? *locations : local;
  if (located.grid != grid || located.sourceKnown.size() != grid.nodeCount() ||
      located.targetKnown.size() != grid.nodeCount()) {
    located.grid = grid;
    located.sourceKnown.assign(grid.nodeCount(), 0);
    located.targetKnown.assign(grid.nodeCount(), 0);
    located.targetPoint.resize(grid.nodeCount());
    located.sourceFace.resize(grid.nodeCount());
    located.sourceBarycentric.resize(grid.nodeCount());
  }
  for (int j = 0; j < grid.height; ++j)
    for (int i = 0; i < grid.width; ++i) {
      const std::size_t n = grid.index(i, j);
      if (!sampled[n]) continue;
      if (!located.sourceKnown[n]) {
        const DomainHit sourceHit = sourceLocator.locate(grid.position(i, j));
        located.sourceFace[n] = sourceHit.face;
        located.sourceBarycentric[n] = sourceHit.barycentric;
        located.sourceKnown[n] = 1;
      }
      if (!located.targetKnown[n]) {
        located.targetPoint[n] = targetLocator.locate(grid.position(i, j)).point;
        located.targetKnown[n] = 1;
      }
      const Eigen::Vector3d offset =
          located.targetPoint[n] -
          draftPoint(draft, canvas, located.sourceFace[n], located.sourceBarycentric[n]);
      for (int c = 0; c < 3; ++c)
        problem.channels[std::size_t(c)][n] = offset[c];
    }
  return setup;
}

Field2D membraneField(const Region2D& region, const MembraneSetup& setup,
                      const std::vector<std::vector<double>>& values) {
  Field2D field;
  field.grid = region.grid;
  field.defined = setup.defined;
  field.values.assign(region.grid.nodeCount(), Eigen::Vector3d::Zero());
  for (std::size_t n = 0; n < field.values.size(); ++n)
    if (field.defined[n]) field.values[n] = {values[0][n], values[1][n], values[2][n]};
  return field;
}

}  // namespace geobrush
