#include "emd.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <string>

#include "geobrush/laplacian.hpp"
#include "geobrush/parallel.hpp"
#include "geobrush/sparse_cholesky.hpp"

namespace geobrush {
namespace {

using Sparse = Eigen::SparseMatrix<double>;

// Whether vertex i ranks above vertex j: a higher value, or the same value and a lower id.
bool ranksAbove(const std::vector<double>& values, int i, int j) {
  return values[i] > values[j] || (values[i] == values[j] && i < j);
}

std::vector<int> extrema(const TriMesh& mesh, const std::vector<double>& values, bool maxima) {
  std::vector<int> found;
  for (auto v : mesh.vertices()) {
    bool extreme = true;
    for (auto w : mesh.vv_range(v)) {
      const bool above = ranksAbove(values, v.idx(), w.idx());
      if (above != maxima) {
        extreme = false;
        break;
      }
    }
    if (extreme) found.push_back(v.idx());
  }
  return found;
}

// The envelope operator (L or L M^-1 L) with every diagonal entry stored, factored symbolically
// once per side: each envelope then only refactors it numerically with its own fixed vertices, the
// upper and the lower one at once on two threads. The harmonic operator's factor stays about as
// sparse as the mesh, which Eigen's simplicial LDL^T factors fastest; the biharmonic one's 2-ring
// operator fills in enough for CHOLMOD's supernodal kernels (SparseCholesky) to win, several
// times over (BENCHMARKS.md, "Sparse Cholesky for the EMD envelopes").
class EnvelopeSolver {
 public:
  EnvelopeSolver(const TriMesh& mesh, Envelope kind) : kind_(kind) {
    const Sparse laplacian = cotangentLaplacian(mesh);
    const int n = int(mesh.n_vertices());
    Sparse diagonal(n, n);
    diagonal.setIdentity();
    if (kind == Envelope::harmonic) {
      operator_ = laplacian + 0.0 * diagonal;
    } else {
      const Eigen::VectorXd areas = vertexAreas(mesh);
      Eigen::VectorXd inverseMass(n);
      for (int i = 0; i < n; ++i)
        inverseMass[i] = areas[i] > 0.0 ? 1.0 / areas[i] : 0.0;
      operator_ = laplacian * inverseMass.asDiagonal() * laplacian + 0.0 * diagonal;
    }
    operator_.makeCompressed();
    isolated_.assign(std::size_t(n), 1);
    for (int j = 0; j < n; ++j)
      for (Sparse::InnerIterator it(operator_, j); it; ++it)
        if (it.row() == j && it.value() != 0.0) isolated_[std::size_t(j)] = 0;
    for (std::size_t side = 0; side < 2; ++side) {
      if (kind_ == Envelope::harmonic)
        simplicial_[side].analyzePattern(operator_);
      else
        supernodal_[side].analyzePattern(operator_);
    }
  }

  // The fields equal to `values` at upper's and lower's fixed vertices (and at isolated vertices)
  // with the operator zero elsewhere.
  std::array<Eigen::VectorXd, 2> through(const std::vector<int>& upper,
                                         const std::vector<int>& lower,
                                         const std::vector<double>& values) {
    std::array<Eigen::VectorXd, 2> fields;
    const std::array<const std::vector<int>*, 2> fixed = {&upper, &lower};
    parallelBlocks(2, 1, 2, [&](std::size_t first, std::size_t last) {
      for (std::size_t side = first; side < last; ++side) {
        const Held held = heldSystem(*fixed[side], values);
        fields[side] = kind_ == Envelope::harmonic ? solve(simplicial_[side], held)
                                                   : solve(supernodal_[side], held);
      }
    });
    return fields;
  }

 private:
  // The operator with the fixed vertices' rows and columns replaced by the identity, and the
  // right-hand side that holds them at their values.
  struct Held {
    Sparse system;
    Eigen::VectorXd rhs;
  };
  Held heldSystem(const std::vector<int>& fixed, const std::vector<double>& values) const {
    std::vector<std::uint8_t> isFixed = isolated_;
    for (int i : fixed)
      isFixed[std::size_t(i)] = 1;
    Held held{operator_, Eigen::VectorXd::Zero(operator_.rows())};
    for (int j = 0; j < held.system.cols(); ++j)
      for (Sparse::InnerIterator it(held.system, j); it; ++it) {
        const int i = int(it.row());
        if (!isFixed[std::size_t(i)] && isFixed[std::size_t(j)])
          held.rhs[i] -= it.value() * values[std::size_t(j)];
        if (isFixed[std::size_t(i)] || isFixed[std::size_t(j)]) it.valueRef() = i == j ? 1.0 : 0.0;
      }
    for (int i = 0; i < int(held.rhs.size()); ++i)
      if (isFixed[std::size_t(i)]) held.rhs[i] = values[std::size_t(i)];
    return held;
  }

  template <typename Solver>
  static Eigen::VectorXd solve(Solver& solver, const Held& held) {
    solver.factorize(held.system);
    if (solver.info() != Eigen::Success)
      throw std::runtime_error("an envelope's system could not be factored");
    return solver.solve(held.rhs);
  }

  Envelope kind_;
  Sparse operator_;
  std::vector<std::uint8_t> isolated_;
  std::array<Eigen::SimplicialLDLT<Sparse>, 2> simplicial_;
  std::array<SparseCholesky, 2> supernodal_;
};

struct SiftResult {
  std::vector<double> mean;  // (e_max + e_min) / 2
  double overshoot = 0.0;    // most s leaves its envelopes by, relative to its range
};

SiftResult envelopeMean(EnvelopeSolver& solver, const std::vector<double>& s,
                        const std::vector<int>& maxima, const std::vector<int>& minima) {
  const auto [upper, lower] = solver.through(maxima, minima, s);
  const auto [lo, hi] = std::minmax_element(s.begin(), s.end());
  const double range = *hi - *lo;
  SiftResult result;
  result.mean.resize(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    const Eigen::Index k = Eigen::Index(i);
    result.mean[i] = 0.5 * (upper[k] + lower[k]);
    const double escape = std::max({s[i] - upper[k], lower[k] - s[i], 0.0});
    if (range > 0.0) result.overshoot = std::max(result.overshoot, escape / range);
  }
  return result;
}

// One intrinsic mode of `s` by sifting; false when s has too few extrema to have one.
bool siftMode(const TriMesh& mesh, EnvelopeSolver& solver, const EmdOptions& options,
              std::vector<double>& s, EmdModeReport& report) {
  for (int sift = 0; sift < options.maxSift; ++sift) {
    const std::vector<int> maxima = localMaxima(mesh, s), minima = localMinima(mesh, s);
    if (sift == 0) {
      report.maxima = int(maxima.size());
      report.minima = int(minima.size());
    }
    if (maxima.size() < 2 || minima.size() < 2) return sift > 0;
    const SiftResult step = envelopeMean(solver, s, maxima, minima);
    double change = 0.0, energy = 0.0;
    for (std::size_t i = 0; i < s.size(); ++i) {
      change += step.mean[i] * step.mean[i];
      energy += s[i] * s[i];
      s[i] -= step.mean[i];
    }
    report.sifts = sift + 1;
    report.overshoot = std::max(report.overshoot, step.overshoot);
    report.lastSd = energy > 0.0 ? change / energy : 0.0;
    if (report.lastSd < options.sdStop) break;
  }
  return true;
}

void checkInputs(const TriMesh& mesh, const std::vector<double>& signal,
                 const EmdOptions& options) {
  if (options.modes < 1 || options.modes > 16) throw std::out_of_range("modes must be in 1..16");
  if (options.maxSift < 1 || options.maxSift > 1000)
    throw std::out_of_range("max_sift must be in 1..1000");
  if (!(options.sdStop > 0.0 && options.sdStop <= 1.0))
    throw std::out_of_range("sd_stop must be in (0, 1]");
  if (signal.size() != mesh.n_vertices())
    throw std::invalid_argument("the signal has " + std::to_string(signal.size()) + " values for " +
                                std::to_string(mesh.n_vertices()) + " vertices");
  for (double value : signal)
    if (!std::isfinite(value)) throw std::invalid_argument("the signal has a non-finite value");
}

}  // namespace

std::vector<int> localMaxima(const TriMesh& mesh, const std::vector<double>& values) {
  return extrema(mesh, values, true);
}

std::vector<int> localMinima(const TriMesh& mesh, const std::vector<double>& values) {
  return extrema(mesh, values, false);
}

EmdResult empiricalModeDecomposition(const TriMesh& mesh, const std::vector<double>& signal,
                                     const EmdOptions& options) {
  checkInputs(mesh, signal, options);
  EnvelopeSolver solver(mesh, options.envelope);
  EmdResult result;
  result.residue = signal;
  for (int k = 0; k < options.modes; ++k) {
    std::vector<double> mode = result.residue;
    EmdModeReport report;
    const bool found = result.modesFound == k && siftMode(mesh, solver, options, mode, report);
    if (!found) mode.assign(signal.size(), 0.0);
    for (std::size_t i = 0; i < mode.size(); ++i)
      result.residue[i] -= mode[i];
    if (found) ++result.modesFound;
    result.modes.push_back(std::move(mode));
    result.reports.push_back(report);
  }
  return result;
}

EmdResult empiricalModeDecomposition(const Canvas& canvas, const std::vector<double>& signal,
                                     const EmdOptions& options) {
  if (signal.size() != canvas.source->surface.n_vertices())
    throw std::invalid_argument("the signal has " + std::to_string(signal.size()) +
                                " values for the canvas' mesh of " +
                                std::to_string(canvas.source->surface.n_vertices()) + " vertices");
  std::vector<double> onCanvas;
  for (int v : canvas.sourceVertex)
    onCanvas.push_back(signal[std::size_t(v)]);
  EmdResult part = empiricalModeDecomposition(canvas.surface, onCanvas, options);
  const auto onMesh = [&](const std::vector<double>& values, std::vector<double> whole) {
    for (std::size_t i = 0; i < values.size(); ++i)
      whole[std::size_t(canvas.sourceVertex[i])] = values[i];
    return whole;
  };
  EmdResult result = part;
  for (std::size_t k = 0; k < part.modes.size(); ++k)
    result.modes[k] = onMesh(part.modes[k], std::vector<double>(signal.size(), 0.0));
  result.residue = onMesh(part.residue, signal);
  return result;
}

}  // namespace geobrush
