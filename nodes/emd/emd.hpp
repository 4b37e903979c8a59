// Empirical mode decomposition of a scalar field on a mesh (EMD detail transfer Eq. 2,
// g = sum_k h_k + r_m), by sifting after Wang et al. 2012, "EMD on surfaces": the local extrema,
// an envelope through the maxima and one through the minima, their mean subtracted until the
// change is small; each intrinsic mode h_k is taken off the signal and the rest sifted again.
#pragma once

#include <vector>

#include "geobrush/canvas.hpp"

namespace geobrush {

enum class Envelope {
  harmonic,    // L e = 0 away from the extrema: bounded by them, kinked at them; a 1-ring factor
  biharmonic,  // L M^-1 L e = 0 away from the extrema: smooth, may overshoot the extrema; a 2-ring
               // factor, several times slower to refactor on every sift
};

struct EmdOptions {
  int modes = 3;        // m: the intrinsic modes h_1..h_m taken off before the residue
  int maxSift = 10;     // sifts per mode at most
  double sdStop = 0.2;  // a mode ends when sum (s_prev - s)^2 / sum s_prev^2 falls below this
  Envelope envelope = Envelope::harmonic;
};

struct EmdModeReport {
  int sifts = 0;           // sifts done for this mode
  int maxima = 0;          // local maxima of the signal the mode started from
  int minima = 0;          // local minima of it
  double lastSd = 0.0;     // the stop criterion at the last sift
  double overshoot = 0.0;  // most the envelopes left [min s, max s] by, over all its sifts
};

struct EmdResult {
  // h_1..h_m, finest first; a mode is all zeros where its signal had fewer than 2 maxima or
  // 2 minima (the decomposition ended before it).
  std::vector<std::vector<double>> modes;
  std::vector<double> residue;  // r_m = signal - sum_k h_k
  std::vector<EmdModeReport> reports;
  int modesFound = 0;  // the modes before the decomposition ended
};

// A vertex is a local maximum (minimum) when its value is above (below) every 1-ring neighbour's,
// ties ordered by vertex id (the lower id counts as greater): every connected part of the mesh
// then has at least one of each.
std::vector<int> localMaxima(const TriMesh& mesh, const std::vector<double>& values);
std::vector<int> localMinima(const TriMesh& mesh, const std::vector<double>& values);

// Eq. 2 on `mesh`. Throws std::invalid_argument when the signal's length is not the vertex count
// or it holds a non-finite value, std::out_of_range for options outside modes 1..16,
// maxSift 1..1000, sdStop in (0, 1], and std::runtime_error when an envelope's system cannot be
// factored.
EmdResult empiricalModeDecomposition(const TriMesh& mesh, const std::vector<double>& signal,
                                     const EmdOptions& options);

// Eq. 2 on a canvas of the mesh `signal` lies on (one value per vertex of canvas.source): its
// surface decomposed, the modes zero and the residue the signal off it; the result's columns are
// per vertex of that mesh. Throws as above, and std::invalid_argument for a signal of another
// length.
EmdResult empiricalModeDecomposition(const Canvas& canvas, const std::vector<double>& signal,
                                     const EmdOptions& options);

}  // namespace geobrush
