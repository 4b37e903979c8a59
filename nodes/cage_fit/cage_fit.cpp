#include "cage_fit.hpp"

#include <Eigen/Dense>
#include <set>

#include "geobrush/domain_locator.hpp"

namespace geobrush {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;

Matrix3d frameMatrix(const Frame& frame) {
  Matrix3d m;
  m.col(0) = frame.uAxis;
  m.col(1) = frame.vAxis;
  m.col(2) = frame.normal;
  return m;
}

}  // namespace

CageFitSolver::CageFitSolver(const Cage& source, double constraintWeight)
    : vertices_(source.mesh.n_vertices()),
      faces_(source.mesh.n_faces()),
      weight_(constraintWeight),
      top_(source.top),
      bottom_(source.bottom) {
  const int n = int(vertices_);
  if (n == 0 || source.top.size() != source.domain.size() ||
      source.bottom.size() != source.domain.size())
    throw CageFitError("the source cage has no columns matching its domain");
  std::vector<Eigen::Triplet<double>> entries;
  for (auto v : source.mesh.vertices()) {
    const double valence = double(source.mesh.valence(v));
    if (valence == 0) throw CageFitError("the source cage has an isolated vertex");
    entries.emplace_back(v.idx(), v.idx(), 1.0);
    for (auto w : source.mesh.vv_range(v))
      entries.emplace_back(v.idx(), w.idx(), -1.0 / valence);
  }
  laplacian_.resize(n, n);
  laplacian_.setFromTriplets(entries.begin(), entries.end());

  // C's boundary: edges used by one domain triangle only.
  std::set<std::pair<int, int>> directed;
  for (const auto& t : source.domainTriangles)
    for (int k = 0; k < 3; ++k)
      directed.emplace(t[k], t[(k + 1) % 3]);
  std::set<int> boundary;
  for (const auto& [a, b] : directed)
    if (!directed.count({b, a})) boundary.insert(a);
  boundaryColumns_.assign(boundary.begin(), boundary.end());
  if (boundaryColumns_.empty()) throw CageFitError("the source cage's domain has no boundary");

  std::vector<Eigen::Triplet<double>> rows;
  for (int r = 0; r < int(boundaryColumns_.size()); ++r) {
    rows.emplace_back(r, top_[boundaryColumns_[r]], 0.5);
    rows.emplace_back(r, bottom_[boundaryColumns_[r]], 0.5);
  }
  constraints_.resize(int(boundaryColumns_.size()), n);
  constraints_.setFromTriplets(rows.begin(), rows.end());

  const Eigen::SparseMatrix<double> system =
      Eigen::SparseMatrix<double>(laplacian_.transpose() * laplacian_) +
      weight_ * weight_ * Eigen::SparseMatrix<double>(constraints_.transpose() * constraints_);
  factor_.compute(system);
  if (factor_.info() != Eigen::Success)
    throw CageFitError("the cage fitting system could not be factored");
}

bool CageFitSolver::fits(const Cage& source, double constraintWeight) const {
  return source.mesh.n_vertices() == vertices_ && source.mesh.n_faces() == faces_ &&
         source.top == top_ && source.bottom == bottom_ && constraintWeight == weight_;
}

Eigen::MatrixX3d CageFitSolver::solve(const Eigen::MatrixX3d& deltas,
                                      const Eigen::MatrixX3d& midpoints) const {
  const Eigen::MatrixX3d rhs =
      laplacian_.transpose() * deltas + weight_ * weight_ * (constraints_.transpose() * midpoints);
  return factor_.solve(rhs);
}

SourceColumns::SourceColumns(const Cage& sourceCage, const Parameterization& source) {
  const DomainLocator locator(source);
  point.reserve(sourceCage.domain.size());
  frame.reserve(sourceCage.domain.size());
  for (const auto& u : sourceCage.domain) {
    const DomainHit hit = locator.locate(u);
    point.push_back(hit.point);
    frame.push_back(frameMatrix(hit.frame()));
  }
}

CageFitResult fitCage(const Cage& sourceCage, const Parameterization& source,
                      const Parameterization& target, const CageFitOptions& options,
                      const CageFitSolver* solver, const SourceColumns* columns) {
  if (!(options.constraintWeight > 0)) throw CageFitError("the constraint weight must be > 0");
  if (!(source.scale > 0) || !(target.scale > 0))
    throw CageFitError("the parameterizations' scales must be > 0");
  std::unique_ptr<CageFitSolver> own;
  if (!solver || !solver->fits(sourceCage, options.constraintWeight)) {
    own = std::make_unique<CageFitSolver>(sourceCage, options.constraintWeight);
    solver = own.get();
  }
  std::unique_ptr<SourceColumns> ownColumns;
  if (!columns) {
    ownColumns = std::make_unique<SourceColumns>(sourceCage, source);
    columns = ownColumns.get();
  }
  if (columns->point.size() != sourceCage.domain.size())
    throw CageFitError("the source columns were found for another cage");
  const DomainLocator targetLocator(target);
  const double lambda = target.scale / source.scale;
  const int n = int(sourceCage.mesh.n_vertices());

  CageFitResult result;
  Eigen::MatrixX3d positions(n, 3);
  for (auto v : sourceCage.mesh.vertices())
    positions.row(v.idx()) = toEigen(sourceCage.mesh.point(v));
  const Eigen::MatrixX3d sourceLaplacians = solver->laplacian() * positions;

  // Per column: T maps the source frame onto the target frame at the same u.
  const std::size_t columnCount = sourceCage.domain.size();
  std::vector<Matrix3d> change(columnCount);
  std::vector<DomainHit> targetHits(columnCount);
  std::vector<Frame> targetFrames(columnCount);
  for (std::size_t d = 0; d < columnCount; ++d) {
    targetHits[d] = targetLocator.locate(sourceCage.domain[d]);
    result.columnsOutsideTarget += !targetHits[d].inside;
    targetFrames[d] = targetHits[d].frame();
    change[d] = frameMatrix(targetFrames[d]) * columns->frame[d].transpose();
  }

  Eigen::MatrixX3d deltas(n, 3);
  for (std::size_t d = 0; d < columnCount; ++d)
    for (int v : {sourceCage.top[d], sourceCage.bottom[d]})
      deltas.row(v) = (lambda * change[d] * sourceLaplacians.row(v).transpose()).transpose();

  // Boundary midpoints keep their offset from the surface, carried by T and
  // lambda: at E_t^-1(u) itself where the source midpoint was at E_s^-1(u).
  const auto& boundary = solver->constrainedColumns();
  Eigen::MatrixX3d midpoints(int(boundary.size()), 3);
  for (int r = 0; r < int(boundary.size()); ++r) {
    const int d = boundary[r];
    const Vector3d mid =
        0.5 * (positions.row(sourceCage.top[d]) + positions.row(sourceCage.bottom[d])).transpose();
    midpoints.row(r) =
        (targetHits[d].point + lambda * change[d] * (mid - columns->point[d])).transpose();
  }

  const Eigen::MatrixX3d fitted = solver->solve(deltas, midpoints);
  if (!fitted.allFinite()) throw CageFitError("the fitted cage has non-finite positions");
  result.cage = sourceCage;
  for (auto v : result.cage.mesh.vertices()) {
    const auto row = fitted.row(v.idx());
    result.cage.mesh.point(v) = {row.x(), row.y(), row.z()};
  }
  result.cage.frames = std::move(targetFrames);
  return result;
}

}  // namespace geobrush
