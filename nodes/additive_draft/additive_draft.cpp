#include "additive_draft.hpp"

#include <Eigen/Geometry>
#include <Eigen/SparseCholesky>
#include <stdexcept>

#include "geobrush/domain_locator.hpp"
#include "geobrush/laplacian.hpp"

namespace geobrush {
namespace {

// The canvas' harmonic surface over its boundary loop in the metric of the (u, v) domain: L B = 0
// inside, L the cotangent Laplacian of the canvas laid flat at its (u, v). It reproduces
// functions linear in (u, v), so a flat canvas is its own base and each base point lies under
// its vertex: the offset from it is the detail alone, with no drift along the surface (weights
// from the surface's own shape would drift, and the drift would read as detail).
TriMesh smoothBase(const Parameterization& source) {
  const TriMesh& surface = source.canvas->surface;
  const int n = int(surface.n_vertices());
  std::vector<int> unknown(std::size_t(n), -1);
  int interior = 0;
  for (auto v : surface.vertices())
    if (!surface.is_boundary(v)) unknown[std::size_t(v.idx())] = interior++;
  if (interior == n)
    throw std::invalid_argument("the source canvas has no boundary to span a base over");
  TriMesh flat = surface;
  for (auto v : flat.vertices()) {
    const Eigen::Vector2d& u = source.uv[std::size_t(v.idx())];
    flat.set_point(v, {u.x(), u.y(), 0.0});
  }
  const Eigen::SparseMatrix<double> laplacian = cotangentLaplacian(flat);
  const Eigen::MatrixX3d points = pointMatrix(surface);
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixX3d rhs = Eigen::MatrixX3d::Zero(interior, 3);
  for (int col = 0; col < n; ++col)
    for (Eigen::SparseMatrix<double>::InnerIterator it(laplacian, col); it; ++it) {
      const int row = unknown[std::size_t(it.row())];
      if (row < 0) continue;
      if (const int c = unknown[std::size_t(col)]; c >= 0)
        entries.emplace_back(row, c, it.value());
      else
        rhs.row(row) -= it.value() * points.row(col);
    }
  Eigen::SparseMatrix<double> system(interior, interior);
  system.setFromTriplets(entries.begin(), entries.end());
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(system);
  if (solver.info() != Eigen::Success)
    throw std::invalid_argument("the source canvas' harmonic base could not be solved");
  const Eigen::MatrixX3d inside = solver.solve(rhs);
  TriMesh base = surface;
  for (auto v : base.vertices())
    if (const int k = unknown[std::size_t(v.idx())]; k >= 0)
      base.set_point(v, {inside(k, 0), inside(k, 1), inside(k, 2)});
  return base;
}

// A frame at a point with unit normal `normal` whose u axis is `towardU` laid into the tangent
// plane: smooth wherever the normal is, unlike the (u, v) jacobian, which jumps from face to face.
Frame frameAt(const Eigen::Vector3d& point, const Eigen::Vector3d& normal,
              const Eigen::Vector3d& towardU) {
  Frame frame;
  frame.point = point;
  frame.normal = normal;
  Eigen::Vector3d u = towardU - towardU.dot(normal) * normal;
  if (u.norm() < 1e-9) u = normal.unitOrthogonal();
  frame.uAxis = u.normalized();
  frame.vAxis = normal.cross(frame.uAxis);
  return frame;
}

// Per-vertex unit vectors of the canvas of `param` interpolated at a hit of its locator.
Eigen::Vector3d interpolated(const std::vector<Eigen::Vector3d>& perVertex,
                             const Parameterization& param, const DomainHit& hit) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int k = 0;
  for (auto v : param.canvas->surface.fv_range(TriMesh::FaceHandle(hit.face)))
    sum += hit.barycentric[k++] * perVertex[std::size_t(v.idx())];
  return sum.norm() > 0.0 ? Eigen::Vector3d(sum.normalized()) : hit.normal;
}

}  // namespace

AdditiveDraft additiveDraft(const Parameterization& source, const Parameterization& target,
                            const AdditiveDraftOptions& options) {
  const TriMesh& surface = source.canvas->surface;
  if (source.uv.size() != surface.n_vertices())
    throw std::invalid_argument("the source parameterization does not cover its canvas");
  AdditiveDraft result;
  result.base = smoothBase(source);
  const std::vector<Eigen::Vector3d> baseNormals = areaWeightedNormals(result.base);
  // The detail leaves the target along its own smooth base's normals: the target's detail (a
  // scan's noise, say) stays where it is without turning the pasted detail with it.
  const std::vector<Eigen::Vector3d> targetBaseNormals = areaWeightedNormals(smoothBase(target));
  const DomainLocator targetLocator(target);
  result.draft = surface;
  for (auto v : surface.vertices()) {
    const std::size_t i = std::size_t(v.idx());
    const Frame from = frameAt(pointOf(result.base, v), baseNormals[i], source.origin.uAxis);
    const Eigen::Vector3d detail = pointOf(surface, v) - from.point;
    result.largestDetail = std::max(result.largestDetail, detail.norm());
    const DomainHit hit = targetLocator.locate(source.uv[i]);
    const Frame to =
        frameAt(hit.point, interpolated(targetBaseNormals, target, hit), target.origin.uAxis);
    const Eigen::Vector3d carried =
        options.gain * target.scale *
        (detail.dot(from.uAxis) * to.uAxis + detail.dot(from.vAxis) * to.vAxis +
         detail.dot(from.normal) * to.normal);
    const Eigen::Vector3d p = to.point + carried;
    result.draft.set_point(v, toPoint(p));
  }
  return result;
}

}  // namespace geobrush
