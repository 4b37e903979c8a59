#include "variational_paste.hpp"

#include <ceres/ceres.h>

#include <Eigen/QR>

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

#include "geobrush/domain_locator.hpp"
#include "variational_paste_cost.hpp"

namespace geobrush {
namespace {

using Eigen::Vector3d;

bool finite(const TriMesh& mesh) {
  for (auto v : mesh.vertices())
    for (int k = 0; k < 3; ++k)
      if (!std::isfinite(mesh.point(v)[k])) return false;
  return true;
}

// Which vertex of the stitched mesh plays which part in the energy (see the header).
struct Roles {
  std::vector<int> unknowns;  // pasted vertices, in mesh order
  std::vector<int> energy;    // vertices whose Laplacian is in the energy: unknowns, then ring 1
  std::vector<int> unknownIndex;  // mesh vertex -> index in `unknowns`, or -1
  std::vector<int> energyIndex;   // mesh vertex -> index in `energy`, or -1
  std::vector<char> ring2;        // fixed neighbours of ring 1 that are not in ring 1
};

Roles classify(const TriMesh& mesh, const PasteMap& map) {
  Roles roles;
  const std::size_t n = mesh.n_vertices();
  roles.unknownIndex.assign(n, -1);
  roles.energyIndex.assign(n, -1);
  roles.ring2.assign(n, 0);
  for (std::size_t v = 0; v < n; ++v)
    if (map.sourceVertex[v] >= 0) {
      roles.unknownIndex[v] = int(roles.unknowns.size());
      roles.energyIndex[v] = int(roles.energy.size());
      roles.unknowns.push_back(int(v));
      roles.energy.push_back(int(v));
    }
  for (int u : roles.unknowns)
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(u)))
      if (roles.energyIndex[std::size_t(w.idx())] < 0) {
        roles.energyIndex[std::size_t(w.idx())] = int(roles.energy.size());
        roles.energy.push_back(w.idx());
      }
  for (std::size_t e = roles.unknowns.size(); e < roles.energy.size(); ++e)
    for (auto w : mesh.vv_range(TriMesh::VertexHandle(roles.energy[e])))
      if (roles.energyIndex[std::size_t(w.idx())] < 0) roles.ring2[std::size_t(w.idx())] = 1;
  return roles;
}

// What the energy reads at every vertex of the unknowns and the two rings (zero elsewhere): g,
// the draft (a pasted vertex's own draft position; at a fixed vertex the draft sampled at its
// target uv on the source canvas), and the vertex's position in the shared parameter domain.
struct DomainSamples {
  std::vector<Vector3d> draft;
  std::vector<Eigen::Vector2d> uv;
};

// Supported draft vertices whose affine fit extends the draft beyond its support. 4 gave
// nearly collinear sets on the support's edge; more reach farther into the relief and bend the
// extension (the seam's normal jump on the mountain-on-sphere clone: p95 28.6 degrees with 6,
// 28.4 with 8, 29.1 with 12, 31.5 with 20; 27.7 with the whole draft read).
constexpr std::size_t kFitVertices = 8;

// The draft where it is defined, G(v) for v in R_in and the region's draft support, and an
// extension elsewhere. A warp of the region (geobrush.gc_warp with its region connected) moves
// only those vertices and leaves the others at their source positions, which in a clone lie on
// the source mesh, anywhere. The fixed rings are target vertices: where the target is coarser
// than the region's grid they reach past the support, which covers two grid nodes beyond Q (the
// membrane's two rings). There the draft is the target plus its detail: g(w) = R_out(w) + d(uv_w),
// with d(u) = G(v) − E_t^-1(u) at the supported vertices v, u = E_s(v), and d extended by the
// least-squares affine map of (u, v) through the kFitVertices supported vertices nearest in the
// domain. Extending the detail rather than the draft keeps the target's curvature (up to its
// linear interpolation between target vertices), and a draft that is the target, or the target
// translated, extends exactly.
class DraftSampler {
 public:
  DraftSampler(const Region2D& region, const Parameterization& source, const TriMesh& draft,
               const Parameterization& target)
      : source_(source), draft_(draft), locator_(source), targetLocator_(target) {
    supported_.assign(source.uv.size(), 0);
    for (const auto* vertices : {&region.sourceVertices, &region.draftSupport})
      for (int v : *vertices)
        supported_[std::size_t(v)] = 1;
    for (std::size_t v = 0; v < supported_.size(); ++v)
      if (supported_[v]) supportList_.push_back(int(v));
  }

  // g at the fixed vertex with domain position `uv` and target position `onTarget`: the draft
  // interpolated where the source face holding uv has its corners in the support.
  Vector3d operator()(const Eigen::Vector2d& uv, const Vector3d& onTarget) const {
    const DomainHit hit = locator_.locate(uv);
    const TriMesh& canvas = source_.canvas->surface;
    bool defined = hit.inside;
    for (auto corner : canvas.fv_range(TriMesh::FaceHandle(hit.face)))
      defined = defined && supported_[std::size_t(corner.idx())];
    if (!defined) return onTarget + extendedDetail(uv);
    Vector3d point = Vector3d::Zero();
    int k = 0;
    for (auto corner : canvas.fv_range(TriMesh::FaceHandle(hit.face)))
      point += hit.barycentric[k++] * pointOf(draft_, corner.idx());
    return point;
  }

 private:
  Vector3d detail(int v) const {
    return pointOf(draft_, v) - targetLocator_.locate(source_.uv[std::size_t(v)]).point;
  }

  Vector3d extendedDetail(const Eigen::Vector2d& uv) const {
    std::vector<std::pair<double, int>> nearest;
    nearest.reserve(supportList_.size());
    for (int v : supportList_)
      nearest.emplace_back((source_.uv[std::size_t(v)] - uv).squaredNorm(), v);
    const std::size_t count = std::min(kFitVertices, nearest.size());
    std::partial_sort(nearest.begin(), nearest.begin() + std::ptrdiff_t(count), nearest.end());
    // d(u_v) ≈ c + J (u_v − uv): the constant c is the value at uv.
    Eigen::MatrixXd a(count, 3);
    Eigen::MatrixXd b(count, 3);
    for (std::size_t i = 0; i < count; ++i) {
      const int v = nearest[i].second;
      a.row(Eigen::Index(i)) << 1.0, (source_.uv[std::size_t(v)] - uv).transpose();
      b.row(Eigen::Index(i)) = detail(v).transpose();
    }
    const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a);
    if (qr.rank() < 3) return detail(nearest.front().second);
    return qr.solve(b).row(0).transpose();
  }

  const Parameterization& source_;
  const TriMesh& draft_;
  const DomainLocator locator_;
  const DomainLocator targetLocator_;
  std::vector<char> supported_;
  std::vector<int> supportList_;
};

DomainSamples sampleDraft(const TriMesh& mesh, const PasteMap& map, const Roles& roles,
                          const Region2D& region, const Parameterization& source,
                          const TriMesh& draft, const Parameterization& target,
                          const StitchBase& base) {
  DomainSamples samples{std::vector<Vector3d>(mesh.n_vertices(), Vector3d::Zero()),
                        std::vector<Eigen::Vector2d>(mesh.n_vertices(), Eigen::Vector2d::Zero())};
  const DraftSampler sampler(region, source, draft, target);
  auto sampleFixed = [&](int v) {
    const int t = map.targetVertex[std::size_t(v)];
    const int c = t >= 0 ? base.meshToCanvas[std::size_t(t)] : -1;
    if (c < 0) {
      throw VariationalPasteError(
          "target vertex " + std::to_string(t) +
          ", two rings from the paste, lies outside the target canvas: paint away from its edge "
          "or grow the target canvas");
    }
    const Eigen::Vector2d& uv = target.uv[std::size_t(c)];
    samples.draft[std::size_t(v)] = sampler(uv, pointOf(mesh, v));
    samples.uv[std::size_t(v)] = uv;
  };
  for (int v : roles.unknowns) {
    const int s = map.sourceVertex[std::size_t(v)];
    samples.draft[std::size_t(v)] = pointOf(draft, s);
    samples.uv[std::size_t(v)] = source.uv[std::size_t(s)];
  }
  for (std::size_t e = roles.unknowns.size(); e < roles.energy.size(); ++e)
    sampleFixed(roles.energy[e]);
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    if (roles.ring2[v]) sampleFixed(int(v));
  return samples;
}

// One row of the Laplacian, L(x)_v = x_v - sum_w lambda_w x_w over v's one-ring.
struct LaplacianRow {
  std::vector<int> vertices;  // v first, then its one-ring
  std::vector<double> weights;
};

LaplacianRow uniformRow(const TriMesh& mesh, int v) {
  LaplacianRow row{{v}, {1.0}};
  for (auto w : mesh.vv_range(TriMesh::VertexHandle(v)))
    row.vertices.push_back(w.idx());
  const double weight = -1.0 / double(row.vertices.size() - 1);
  row.weights.resize(row.vertices.size(), weight);
  row.weights[0] = 1;
  return row;
}

// tan(alpha / 2) for the angle alpha between a and b, without trigonometry.
double halfAngleTangent(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const double cross = std::abs(a.x() * b.y() - a.y() * b.x());
  return cross / (a.norm() * b.norm() + a.dot(b));
}

// Floater's mean-value weights at v in the parameter domain, lambda_w proportional to
// (tan(alpha/2) + tan(beta/2)) / |uv_w - uv_v| with alpha, beta the angles at v of the two faces
// on edge vw. Unsigned angles keep every weight positive even where the fan folds over in the
// domain; a degenerate fan (coincident uv, a straight angle) falls back to uniform weights.
LaplacianRow meanValueRow(const TriMesh& mesh, int v, const std::vector<Eigen::Vector2d>& uv) {
  LaplacianRow row{{v}, {1.0}};
  const Eigen::Vector2d& centre = uv[std::size_t(v)];
  // The angle at v of the face of h, an outgoing halfedge of v (none on the boundary).
  auto angleTangent = [&](TriMesh::HalfedgeHandle h) {
    if (!mesh.face_handle(h).is_valid()) return 0.0;
    const int a = mesh.to_vertex_handle(h).idx();
    const int b = mesh.to_vertex_handle(mesh.next_halfedge_handle(h)).idx();
    return halfAngleTangent(uv[std::size_t(a)] - centre, uv[std::size_t(b)] - centre);
  };
  double total = 0;
  for (auto h : mesh.voh_range(TriMesh::VertexHandle(v))) {
    const int w = mesh.to_vertex_handle(h).idx();
    // The other face on edge vw is that of the outgoing halfedge after opposite(h).
    const auto other = mesh.next_halfedge_handle(mesh.opposite_halfedge_handle(h));
    const double weight =
        (angleTangent(h) + angleTangent(other)) / (uv[std::size_t(w)] - centre).norm();
    row.vertices.push_back(w);
    row.weights.push_back(weight);
    total += weight;
  }
  if (!std::isfinite(total) || !(total > 0)) return uniformRow(mesh, v);
  for (std::size_t i = 1; i < row.weights.size(); ++i) {
    if (!std::isfinite(row.weights[i])) return uniformRow(mesh, v);
    row.weights[i] = -row.weights[i] / total;
  }
  return row;
}

Vector3d laplacianOf(const LaplacianRow& row, const std::vector<Vector3d>& x) {
  Vector3d sum = Vector3d::Zero();
  for (std::size_t i = 0; i < row.vertices.size(); ++i)
    sum += row.weights[i] * x[std::size_t(row.vertices[i])];
  return sum;
}

// The unknowns: three scalar blocks per pasted vertex (x, y, z), and one angle-axis block per
// vertex of the energy in the rotation-invariant mode.
struct Unknowns {
  std::vector<double> x;  // 3 per pasted vertex
  std::vector<double> rotation;
  double* coordinate(int unknown, int k) { return &x[3 * std::size_t(unknown) + std::size_t(k)]; }
  double* angleAxis(int e) { return &rotation[3 * std::size_t(e)]; }
};

struct Problem {
  const TriMesh& mesh;
  const Roles& roles;
  std::vector<LaplacianRow> rows;  // per energy vertex
  std::vector<Vector3d> delta;     // per energy vertex: L(g)_v
  std::vector<Vector3d> fixed;     // per mesh vertex: the target position (fixed vertices)
};

// Adds the three coordinate rows of energy vertex e; `rotated` lets R_e act on δ_e.
void addLaplacianResiduals(ceres::Problem& ceresProblem, const Problem& problem, Unknowns& unknowns,
                           std::size_t e, bool rotated) {
  const LaplacianRow& row = problem.rows[e];
  for (int k = 0; k < 3; ++k) {
    std::vector<double> coefficients;
    std::vector<double*> blocks;
    double constant = rotated ? 0.0 : -problem.delta[e][k];
    for (std::size_t i = 0; i < row.vertices.size(); ++i) {
      const int u = problem.roles.unknownIndex[std::size_t(row.vertices[i])];
      if (u < 0) {
        constant += row.weights[i] * problem.fixed[std::size_t(row.vertices[i])][k];
        continue;
      }
      coefficients.push_back(row.weights[i]);
      blocks.push_back(unknowns.coordinate(u, k));
    }
    ceres::CostFunction* cost = nullptr;
    if (rotated) {
      cost = new LaplacianResidual(std::move(coefficients), constant, problem.delta[e], k);
      blocks.push_back(unknowns.angleAxis(int(e)));
    } else {
      cost = new LaplacianResidual(std::move(coefficients), constant);
    }
    // Every row has a parameter block, as Ceres requires: a ring-1 vertex has an unknown
    // neighbour by definition.
    ceresProblem.AddResidualBlock(cost, nullptr, blocks);
  }
}

double rootMeanSquareNorm(const std::vector<Vector3d>& values) {
  double sum = 0;
  for (const auto& v : values)
    sum += v.squaredNorm();
  return values.empty() ? 0 : std::sqrt(sum / double(values.size()));
}

// The ring-fit term of energy vertex e: for each neighbour w and coordinate k,
// s ((x_w - x_v) - R_v (g_w - g_v))_k, so that R_v is the rotation that turns v's draft one-ring
// onto its result one-ring (as-rigid-as-possible): without it a detail sheared whole would cost
// nothing, since L has linear precision and R_v could turn δ_v to any side.
void addRingFitResiduals(ceres::Problem& ceresProblem, const Problem& problem,
                         const std::vector<Vector3d>& g, Unknowns& unknowns, std::size_t e,
                         double weight) {
  const LaplacianRow& row = problem.rows[e];
  const int v = row.vertices[0];
  for (std::size_t i = 1; i < row.vertices.size(); ++i) {
    const int w = row.vertices[i];
    const Vector3d edge = weight * (g[std::size_t(w)] - g[std::size_t(v)]);
    for (int k = 0; k < 3; ++k) {
      std::vector<double> coefficients;
      std::vector<double*> blocks;
      double constant = 0;
      for (const auto& [vertex, sign] : {std::pair{w, 1.0}, std::pair{v, -1.0}}) {
        const int u = problem.roles.unknownIndex[std::size_t(vertex)];
        if (u < 0) {
          constant += sign * weight * problem.fixed[std::size_t(vertex)][k];
          continue;
        }
        coefficients.push_back(sign * weight);
        blocks.push_back(unknowns.coordinate(u, k));
      }
      blocks.push_back(unknowns.angleAxis(int(e)));
      ceresProblem.AddResidualBlock(
          new LaplacianResidual(std::move(coefficients), constant, edge, k), nullptr, blocks);
    }
  }
}

// s of the ring-fit term: `relative` times the RMS |δ| over the RMS draft edge length, so that a
// rotation error costs about as much in either term. Zero when the draft has no detail (δ = 0):
// there is nothing to turn.
double ringFitWeight(const Problem& problem, const std::vector<Vector3d>& g, double relative) {
  double edges = 0;
  std::size_t count = 0;
  for (const LaplacianRow& row : problem.rows)
    for (std::size_t i = 1; i < row.vertices.size(); ++i, ++count)
      edges += (g[std::size_t(row.vertices[i])] - g[std::size_t(row.vertices[0])]).squaredNorm();
  const double length = count ? std::sqrt(edges / double(count)) : 0;
  return length > 0 ? relative * rootMeanSquareNorm(problem.delta) / length : 0;
}

// Stops a solve when cancelled, and reports its iterations as progress within its stage.
class SolverCallback final : public ceres::IterationCallback {
 public:
  SolverCallback(const VariationalPasteOptions& options, double stageStart)
      : options_(options), stageStart_(stageStart) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& iteration) override {
    if (options_.cancelled && options_.cancelled()) return ceres::SOLVER_ABORT;
    if (options_.progress)
      options_.progress(stageStart_ + 0.5 * std::min(1.0, double(iteration.iteration) /
                                                              double(options_.maxIterations)));
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const VariationalPasteOptions& options_;
  double stageStart_;
};

ceres::Solver::Summary solve(ceres::Problem& problem, const VariationalPasteOptions& options,
                             bool linear) {
  ceres::Solver::Options solverOptions;
  solverOptions.minimizer_type = ceres::TRUST_REGION;
  solverOptions.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  solverOptions.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(ceres::SUITE_SPARSE))
    solverOptions.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  // The linear problem's first step is its Gauss-Newton step when the damping is negligible;
  // with Ceres' default radius (1e4) the bi-Laplacian's smooth modes take several more
  // factorizations to converge.
  if (linear) solverOptions.initial_trust_region_radius = 1e12;
  solverOptions.max_num_iterations = options.maxIterations;
  solverOptions.function_tolerance = options.tolerance;
  // Ceres' gradient tolerance is absolute, and our energies scale with the mesh's size squared
  // (a small patch's gradient is below the default 1e-10 before the first step): only the
  // relative tests, on the energy and on the step, decide convergence.
  solverOptions.gradient_tolerance = 0;
  solverOptions.num_threads = std::max(1, options.threads);
  solverOptions.logging_type = ceres::SILENT;
  solverOptions.minimizer_progress_to_stdout = false;
  SolverCallback callback(options, linear ? 0.0 : 0.5);
  solverOptions.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(solverOptions, &problem, &summary);
  return summary;
}

void requireConvergence(const ceres::Solver::Summary& summary,
                        const VariationalPasteOptions& options, const char* stage) {
  if (summary.termination_type == ceres::CONVERGENCE) return;
  const bool cancelled = summary.termination_type == ceres::USER_FAILURE;
  std::ostringstream message;
  message << "the " << stage << " solve ";
  if (cancelled)
    message << "was cancelled";
  else
    message << "did not converge after " << summary.iterations.size() - 1 << " iterations (at most "
            << options.maxIterations << ", tolerance " << options.tolerance
            << "): " << summary.message;
  throw VariationalPasteSolveError(message.str(), cancelled);
}

}  // namespace

VariationalPasteResult variationalPaste(const Region2D& region, const Parameterization& source,
                                        const TriMesh& draft, const Parameterization& target,
                                        const VariationalPasteOptions& options,
                                        const StitchBase* base) {
  if (options.maxIterations < 1) throw VariationalPasteError("maxIterations must be at least 1");
  if (!(options.tolerance > 0)) throw VariationalPasteError("the tolerance must be positive");
  if (!finite(draft)) throw VariationalPasteError("the draft has non-finite vertex positions");
  VariationalPasteResult result;
  std::optional<StitchBase> ownBase;
  try {
    if (!base) base = &ownBase.emplace(stitchBase(target));
    StitchResult stitched = stitchPaste(region, source, draft, nullptr, target, base);
    result.mesh = std::move(stitched.mesh);
    result.map = std::move(stitched.map);
  } catch (const StitchError& e) {
    throw VariationalPasteError(e.what());
  }
  TriMesh& mesh = result.mesh;
  const Roles roles = classify(mesh, result.map);
  VariationalPasteReport& report = result.report;
  report.unknownVertices = roles.unknowns.size();
  report.ringVertices = roles.energy.size() - roles.unknowns.size();
  if (roles.unknowns.empty()) return result;

  Problem problem{mesh, roles, {}, {}, {}};
  const DomainSamples samples =
      sampleDraft(mesh, result.map, roles, region, source, draft, target, *base);
  const std::vector<Vector3d>& g = samples.draft;
  problem.fixed.assign(mesh.n_vertices(), Vector3d::Zero());
  for (std::size_t v = 0; v < mesh.n_vertices(); ++v)
    if (roles.unknownIndex[v] < 0) problem.fixed[v] = pointOf(mesh, int(v));
  for (int v : roles.energy) {
    problem.rows.push_back(options.weights == LaplacianWeights::MeanValue
                               ? meanValueRow(mesh, v, samples.uv)
                               : uniformRow(mesh, v));
    problem.delta.push_back(laplacianOf(problem.rows.back(), g));
  }

  // The linear solve (Eq. 3 as it stands), from x = G.
  Unknowns unknowns;
  unknowns.x.reserve(3 * roles.unknowns.size());
  for (int v : roles.unknowns)
    for (int k = 0; k < 3; ++k)
      unknowns.x.push_back(g[std::size_t(v)][k]);
  {
    ceres::Problem linear;
    for (std::size_t e = 0; e < roles.energy.size(); ++e)
      addLaplacianResiduals(linear, problem, unknowns, e, false);
    const ceres::Solver::Summary summary = solve(linear, options, true);
    requireConvergence(summary, options, "linear");
    report.linearIterations = int(summary.iterations.size()) - 1;
    report.initialEnergy = 2 * summary.initial_cost;
    report.finalEnergy = 2 * summary.final_cost;
    report.solver = summary.BriefReport();
  }

  // The rotation-invariant solve, from the linear solution with every rotation the identity.
  const double fitWeight = ringFitWeight(problem, g, options.rotationWeight);
  if (options.rotationInvariant && fitWeight > 0) {
    unknowns.rotation.assign(3 * roles.energy.size(), 0.0);
    ceres::Problem rotated;
    for (std::size_t e = 0; e < roles.energy.size(); ++e) {
      addLaplacianResiduals(rotated, problem, unknowns, e, true);
      addRingFitResiduals(rotated, problem, g, unknowns, e, fitWeight);
    }
    const ceres::Solver::Summary summary = solve(rotated, options, false);
    requireConvergence(summary, options, "rotation-invariant");
    report.rotations = roles.energy.size();
    report.rotationIterations = int(summary.iterations.size()) - 1;
    report.finalEnergy = 2 * summary.final_cost;
    report.solver = summary.BriefReport();
  }

  for (std::size_t u = 0; u < roles.unknowns.size(); ++u)
    mesh.set_point(TriMesh::VertexHandle(roles.unknowns[u]),
                   {unknowns.x[3 * u], unknowns.x[3 * u + 1], unknowns.x[3 * u + 2]});
  if (!finite(mesh))
    throw VariationalPasteSolveError("the solve gave non-finite vertex positions", false);
  return result;
}

}  // namespace geobrush
