// The levels of the membrane's Galerkin multigrid (GeoBrush paper section 4.4, Eq. 4) and the
// kernels that apply their operators.
#include "membrane_levels.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <utility>

#include "geobrush/parallel.hpp"
#include "geobrush/simd.hpp"

// Every kernel below runs through simd::fastest: compiled for AVX2 and for the baseline, the
// same arithmetic in both (geobrush/simd.hpp).

namespace geobrush::membrane_detail {
namespace {

// Prolongation is the cubic B-spline subdivision rule: the weight of a coarse node at a fine node
// `offset` fine steps away along one axis (a tensor product in 2D). Bilinear prolongation is not
// enough for a fourth-order operator: its piecewise-linear coarse functions have kinks whose
// discrete curvature costs plate energy, so the Galerkin coarse levels only half-correct smooth
// errors, and with a V-cycle that loss compounds level by level (CG needed 14, 20 and 26
// iterations at 64^2, 128^2 and 256^2). B-splines are C2, and the coarse stencils grow only from
// 25 to 49 points.
constexpr int kSplineReach = 2;
constexpr double splineWeight(int offset) {
  switch (offset) {
    case 0:
      return 0.75;
    case 1:
    case -1:
      return 0.5;
    case 2:
    case -2:
      return 0.125;
    default:
      return 0;
  }
}

// The fine coordinate under coarse coordinate `coarse`. The coarse grid starts one coarse step
// before the fine grid, so that coarse unknowns stay at least one node from every grid border.
constexpr int fineOf(int coarse) {
  return 2 * coarse - 2;
}

Stencil plateStencil() {
  Stencil s{};
  s[stencilSlot(0, 0)] = 20;
  for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
    s[stencilSlot(dx, dy)] = -8;
    s[stencilSlot(2 * dx, 2 * dy)] = 1;
  }
  for (auto [dx, dy] : {std::pair{1, 1}, {-1, 1}, {1, -1}, {-1, -1}})
    s[stencilSlot(dx, dy)] = 2;
  return s;
}

Stencil laplaceStencil() {
  Stencil s{};
  s[stencilSlot(0, 0)] = 4;
  for (auto [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
    s[stencilSlot(dx, dy)] = -1;
  return s;
}

constexpr int kGalerkinWindow = kSplineReach + kReach;
constexpr int kGalerkinSide = 2 * kGalerkinWindow + 1;
using GalerkinWindow = std::array<std::array<double, kGalerkinSide>, kGalerkinSide>;

// R w for w = A P e_I on the fine window around coarse node I: the coarse stencil row, restricted
// one axis at a time. The coarse node j steps away covers fine offsets 2j - 2 .. 2j + 2.
Stencil restrictWindow(const GalerkinWindow& w) {
  constexpr int kWindow = kGalerkinWindow;
  constexpr int kSide = kGalerkinSide;
  std::array<std::array<double, kStencilSide>, kSide> halfway{};
  for (int gy = 0; gy < kSide; ++gy)
    for (int jx = -kReach; jx <= kReach; ++jx)
      for (int dx = -kSplineReach; dx <= kSplineReach; ++dx) {
        const int gx = 2 * jx + dx + kWindow;
        if (gx < 0 || gx >= kSide) continue;
        halfway[std::size_t(gy)][std::size_t(jx + kReach)] +=
            splineWeight(dx) * w[std::size_t(gy)][std::size_t(gx)];
      }
  Stencil row{};
  for (int jy = -kReach; jy <= kReach; ++jy)
    for (int dy = -kSplineReach; dy <= kSplineReach; ++dy) {
      const int gy = 2 * jy + dy + kWindow;
      if (gy < 0 || gy >= kSide) continue;
      for (int jx = -kReach; jx <= kReach; ++jx)
        row[std::size_t(stencilSlot(jx, jy))] +=
            splineWeight(dy) * halfway[std::size_t(gy)][std::size_t(jx + kReach)];
    }
  return row;
}

// The Galerkin product P^T S P of a stencil on the unmasked infinite grid: the coarse operator
// wherever Q is far away. S P e_0 is gathered on the fine window it reaches and restricted, as
// galerkinRow does near the boundary (so that its rows away from the boundary equal this one).
Stencil galerkinStencil(const Stencil& fine) {
  GalerkinWindow w{};
  for (int fy = -kSplineReach; fy <= kSplineReach; ++fy)
    for (int fx = -kSplineReach; fx <= kSplineReach; ++fx)
      for (int ky = -kReach; ky <= kReach; ++ky)
        for (int kx = -kReach; kx <= kReach; ++kx)
          w[std::size_t(fy + ky + kGalerkinWindow)][std::size_t(fx + kx + kGalerkinWindow)] +=
              splineWeight(fx) * splineWeight(fy) * fine[std::size_t(stencilSlot(kx, ky))];
  return restrictWindow(w);
}

const Stencil& rowWeights(const Level& level, int node) {
  const int custom = level.customOfNode[std::size_t(node)];
  return custom < 0 ? level.regular : level.customRows[std::size_t(custom)].weights;
}

// w += A P e_I before masking: the columns of A (its rows: the operators are symmetric) at the
// fine unknowns under the B-spline of coarse node I, weighted by the spline. Reach is the fine
// stencil's, as a constant so that the loops unroll.
template <int Reach>
void gatherColumns(const Level& fine, int centerX, int centerY, const GalerkinWindow& unknown,
                   GalerkinWindow& w) {
  for (int fy = -kSplineReach; fy <= kSplineReach; ++fy)
    for (int fx = -kSplineReach; fx <= kSplineReach; ++fx) {
      if (unknown[std::size_t(fy + kGalerkinWindow)][std::size_t(fx + kGalerkinWindow)] == 0)
        continue;
      const double pf = splineWeight(fx) * splineWeight(fy);
      const Stencil& a = rowWeights(fine, fine.grid.index(centerX + fx, centerY + fy));
      for (int ky = -Reach; ky <= Reach; ++ky) {
        double* out = w[std::size_t(fy + ky + kGalerkinWindow)].data() + fx + kGalerkinWindow;
        const double* column = a.data() + stencilSlot(0, ky);
        for (int kx = -Reach; kx <= Reach; ++kx)
          out[kx] += pf * column[kx];
      }
    }
}

// Row (coarseX, coarseY) of R A P from the fine level's rows and mask: exact also where the mask
// cuts the B-splines short. w = A P e_I is gathered on the fine window it can reach, then
// restricted to the coarse stencil one axis at a time.
Stencil galerkinRowOnce(const Level& fine, int coarseX, int coarseY) {
  constexpr int kWindow = kGalerkinWindow;
  constexpr int kSide = kGalerkinSide;
  const int centerX = fineOf(coarseX), centerY = fineOf(coarseY);
  GalerkinWindow unknown{};  // 1 or 0: multiplied, not branched on
  for (int gy = -kWindow; gy <= kWindow; ++gy)
    for (int gx = -kWindow; gx <= kWindow; ++gx) {
      const int x = centerX + gx, y = centerY + gy;
      if (fine.grid.contains(x, y))
        unknown[std::size_t(gy + kWindow)][std::size_t(gx + kWindow)] =
            fine.mask[std::size_t(fine.grid.index(x, y))];
    }
  GalerkinWindow w{};
  switch (fine.reach) {
    case 1:
      gatherColumns<1>(fine, centerX, centerY, unknown, w);
      break;
    case 2:
      gatherColumns<2>(fine, centerX, centerY, unknown, w);
      break;
    default:
      gatherColumns<kReach>(fine, centerX, centerY, unknown, w);
      break;
  }
  // Masked once here rather than term by term: the same values (the mask is 0 or 1).
  for (int gy = 0; gy < kSide; ++gy)
    for (int gx = 0; gx < kSide; ++gx)
      w[std::size_t(gy)][std::size_t(gx)] *= unknown[std::size_t(gy)][std::size_t(gx)];
  return restrictWindow(w);
}

Stencil galerkinRow(const Level& fine, int coarseX, int coarseY) {
  return simd::fastest([&] { return galerkinRowOnce(fine, coarseX, coarseY); });
}

// Box dilation of `marks` by `radius` nodes (Chebyshev distance): separable, each pass an OR of
// shifted copies.
std::vector<std::uint8_t> dilate(const PaddedGrid& grid, const std::vector<std::uint8_t>& marks,
                                 int radius) {
  const int stride = grid.stride(), rows = grid.rows();
  std::vector<std::uint8_t> horizontal(marks.size(), 0), out(marks.size(), 0);
  for (int y = 0; y < rows; ++y) {
    const std::uint8_t* in = marks.data() + std::size_t(y) * std::size_t(stride);
    std::uint8_t* row = horizontal.data() + std::size_t(y) * std::size_t(stride);
    for (int shift = -radius; shift <= radius; ++shift)
      for (int x = std::max(0, -shift); x < std::min(stride, stride - shift); ++x)
        row[x] |= in[x + shift];
  }
  for (int y = 0; y < rows; ++y) {
    std::uint8_t* row = out.data() + std::size_t(y) * std::size_t(stride);
    for (int from = std::max(0, y - radius); from <= std::min(rows - 1, y + radius); ++from) {
      const std::uint8_t* in = horizontal.data() + std::size_t(from) * std::size_t(stride);
      for (int x = 0; x < stride; ++x)
        row[x] |= in[x];
    }
  }
  return out;
}

double gershgorinRatio(const Stencil& row) {
  double sum = 0;
  for (double w : row)
    sum += std::abs(w);
  return sum / row[stencilSlot(0, 0)];
}

// The Lanczos estimate is a lower bound (within 4% after 8 steps on the coarse levels tried);
// the Chebyshev smoother amplifies eigenvalues beyond (1 + 1 / smootherRatio) times its upper end.
constexpr double kLanczosSafety = 1.1;

double largestRitzValue(const Level& level);

// Everything a level derives from its mask, regular stencil and custom rows.
void finishLevel(Level& level, int bandWidth) {
  const PaddedGrid& grid = level.grid;
  const std::size_t size = grid.size();

  level.unknowns.clear();
  level.spans.assign(std::size_t(grid.height), RowSpan{});
  for (int y = 0; y < grid.height; ++y) {
    RowSpan& span = level.spans[std::size_t(y)];
    for (int x = 0; x < grid.width; ++x) {
      const int node = grid.index(x, y);
      if (level.mask[std::size_t(node)] == 0) continue;
      if (span.begin == span.end) span.begin = node;
      span.end = node + 1;
      level.unknowns.push_back(node);
    }
  }
  level.activeBegin = level.unknowns.empty() ? 0 : level.unknowns.front();
  level.activeEnd = level.unknowns.empty() ? 0 : level.unknowns.back() + 1;

  for (int dy = -kReach; dy <= kReach; ++dy)
    for (int dx = -kReach; dx <= kReach; ++dx)
      level.slotOffsets[std::size_t(stencilSlot(dx, dy))] = dy * grid.stride() + dx;

  level.customOfNode.assign(size, -1);
  level.customBegin.assign(std::size_t(grid.height) + 1, 0);
  for (std::size_t i = 0; i < level.customRows.size(); ++i) {
    const int node = level.customRows[i].node;
    level.customOfNode[std::size_t(node)] = int(i);
    ++level.customBegin[std::size_t(node / grid.stride() - kPad) + 1];
  }
  for (int y = 0; y < grid.height; ++y)
    level.customBegin[std::size_t(y) + 1] += level.customBegin[std::size_t(y)];

  level.inverseDiagonal.assign(size, 0);
  level.lambdaMax = gershgorinRatio(level.regular);
  for (int node : level.unknowns)
    level.inverseDiagonal[std::size_t(node)] = 1 / rowWeights(level, node)[stencilSlot(0, 0)];
  for (const CustomRow& row : level.customRows)
    level.lambdaMax = std::max(level.lambdaMax, gershgorinRatio(row.weights));

  std::vector<std::uint8_t> outside(size);
  for (std::size_t i = 0; i < size; ++i)
    outside[i] = level.mask[i] == 0;
  const std::vector<std::uint8_t> nearOutside = dilate(grid, outside, bandWidth);
  level.band.clear();
  for (int node : level.unknowns)
    if (nearOutside[std::size_t(node)]) level.band.push_back(node);

  level.mirrored = true;
  for (int dy = -kReach; dy <= kReach; ++dy)
    for (int dx = -kReach; dx <= kReach; ++dx) {
      const double w = level.regular[std::size_t(stencilSlot(dx, dy))];
      level.mirrored = level.mirrored && w == level.regular[std::size_t(stencilSlot(-dx, dy))] &&
                       w == level.regular[std::size_t(stencilSlot(dx, -dy))];
    }

  SingleCoefficients& single = level.single;
  single.mask.assign(level.mask.begin(), level.mask.end());
  single.inverseDiagonal.assign(level.inverseDiagonal.begin(), level.inverseDiagonal.end());
  std::copy(level.regular.begin(), level.regular.end(), single.regular.begin());
  single.custom.resize(level.customRows.size());
  single.customPadded.assign(level.customRows.size(), PaddedStencil{});
  for (std::size_t c = 0; c < level.customRows.size(); ++c) {
    const Stencil& weights = level.customRows[c].weights;
    std::copy(weights.begin(), weights.end(), single.custom[c].begin());
    for (int row = 0; row < kStencilSide; ++row)
      std::copy_n(weights.begin() + row * kStencilSide, kStencilSide,
                  single.customPadded[c].begin() + row * kPaddedSide);
  }
}

// The coefficients a kernel reads in its precision: the double ones, or their float copies.
template <typename T>
struct Coefficients;

template <>
struct Coefficients<double> {
  static const double* mask(const Level& level) { return level.mask.data(); }
  static const double* inverseDiagonal(const Level& level) { return level.inverseDiagonal.data(); }
  static const double* regular(const Level& level) { return level.regular.data(); }
};

template <>
struct Coefficients<float> {
  static const float* mask(const Level& level) { return level.single.mask.data(); }
  static const float* inverseDiagonal(const Level& level) {
    return level.single.inverseDiagonal.data();
  }
  static const float* regular(const Level& level) { return level.single.regular.data(); }
};

// Whole 32-byte vectors of T (GCC's vector extension, which Clang honours too), for loops whose
// shifted loads the compilers would otherwise carry from one iteration to the next as scalars and
// then not vectorize. Lane by lane the arithmetic is the scalar code's, so results are the same.
// Every function passing a vector is inlined into its kernel, so no vector crosses a call and the
// baseline copy's calling convention (-Wpsabi, off for this file) never applies.
template <typename T>
struct Packed {
  using Vector [[gnu::vector_size(32)]] = T;
  static constexpr int width = int(sizeof(Vector) / sizeof(T));
  [[gnu::always_inline]] static Vector load(const T* p) {
    Vector v;
    std::memcpy(&v, p, sizeof v);
    return v;
  }
  [[gnu::always_inline]] static void store(T* p, Vector v) { std::memcpy(p, &v, sizeof v); }
  [[gnu::always_inline]] static Vector splat(T value) {
    Vector v;
    for (int k = 0; k < width; ++k)
      v[k] = value;
    return v;
  }
};

// One T at a time, for the elements after the last whole vector.
template <typename T>
struct Single {
  [[gnu::always_inline]] static T load(const T* p) { return *p; }
  [[gnu::always_inline]] static void store(T* p, T v) { *p = v; }
  [[gnu::always_inline]] static T splat(T value) { return value; }
};

// step(lanes, i) for i in [0, length): whole vectors from i = 0, then single elements.
template <typename T, typename Step>
[[gnu::always_inline]] inline void forEachLane(int length, Step&& step) {
  int i = 0;
  for (; i + Packed<T>::width <= length; i += Packed<T>::width)
    step(Packed<T>{}, i);
  for (; i < length; ++i)
    step(Single<T>{}, i);
}
// The stencils: (S x) at node i of a padded array x with row stride s, one type per form of S,
// each summing in its own fixed order. Always inlined: a call in the kernels' loops would stop
// their vectorization.

// The finest level's 13-point plate (Delta^2 of the 5-point Laplacian), written out.
struct PlateTaps {
  template <typename T>
  [[gnu::always_inline]] T at(const T* x, int i, int s) const {
    return T(20) * x[i] - T(8) * (x[i - 1] + x[i + 1] + x[i - s] + x[i + s]) +
           T(2) * (x[i - s - 1] + x[i - s + 1] + x[i + s - 1] + x[i + s + 1]) +
           (x[i - 2] + x[i + 2] + x[i - 2 * s] + x[i + 2 * s]);
  }
};

// The plate for a Gauss-Seidel sweep, whose previous steps have just written the nodes to the
// left or right of i: those taps come last, so that the sweep's chain of dependent operations
// (store, load, multiply, add) stays short.
struct PlateSweepTaps {
  template <typename T>
  [[gnu::always_inline]] T at(const T* x, int i, int s) const {
    const T others = T(20) * x[i] - T(8) * (x[i - s] + x[i + s]) +
                     T(2) * (x[i - s - 1] + x[i - s + 1] + x[i + s - 1] + x[i + s + 1]) +
                     (x[i - 2 * s] + x[i + 2 * s]);
    return others + (T(-8) * (x[i - 1] + x[i + 1]) + (x[i - 2] + x[i + 2]));
  }
};

// The finest level's 5-point Laplacian, written out.
struct LaplaceTaps {
  template <typename T>
  [[gnu::always_inline]] T at(const T* x, int i, int s) const {
    return T(4) * x[i] - (x[i - 1] + x[i + 1] + x[i - s] + x[i + s]);
  }
};

// 49 weights (a coarse level's regular stencil, or a custom row in double), one stencil row at a
// time.
template <typename T>
struct WeightTaps {
  const T* weights;
  bool mirrored;  // w(dx, dy) = w(-dx, dy) = w(dx, -dy), exactly
  [[gnu::always_inline]] T at(const T* x, int i, int s) const {
    T sum = 0;
    for (int dy = -kReach; dy <= kReach; ++dy) {
      const T* row = x + i + dy * s;
      const T* w = weights + stencilSlot(0, dy);
      sum += w[-3] * row[-3] + w[-2] * row[-2] + w[-1] * row[-1] + w[0] * row[0] + w[1] * row[1] +
             w[2] * row[2] + w[3] * row[3];
    }
    return sum;
  }
};

// A custom row in single precision from its padded weights: eight lanes summed down the stencil
// rows, then added pairwise. Plain code in a fixed order, so that every build rounds alike.
struct PaddedTaps {
  const float* weights;
  [[gnu::always_inline]] float at(const float* x, int i, int s) const {
    using Lanes = Packed<float>;
    static_assert(Lanes::width == kPaddedSide);
    Lanes::Vector lanes = Lanes::splat(0.0f);
    for (int dy = -kReach; dy <= kReach; ++dy) {
      const float* row = x + i + dy * s - kReach;
      lanes += Lanes::load(weights + (dy + kReach) * kPaddedSide) * Lanes::load(row);
    }
    return ((lanes[0] + lanes[4]) + (lanes[2] + lanes[6])) +
           ((lanes[1] + lanes[5]) + (lanes[3] + lanes[7]));
  }
};

// A loop whose iterations write disjoint elements that no other iteration reads: the compiler
// cannot prove it through the kernels' pointers. Clang's form also demands vectorization, which
// an instrumented (AddressSanitizer) or unoptimized build cannot give.
#if defined(__clang__)
#if defined(__OPTIMIZE__) && !__has_feature(address_sanitizer)
#define GEOBRUSH_INDEPENDENT_ITERATIONS _Pragma("clang loop vectorize(assume_safety)")
#else
#define GEOBRUSH_INDEPENDENT_ITERATIONS
#endif
#elif defined(__GNUC__)
#define GEOBRUSH_INDEPENDENT_ITERATIONS _Pragma("GCC ivdep")
#else
#define GEOBRUSH_INDEPENDENT_ITERATIONS
#endif

// sum[i] = (S x)[center + i] for i < length, a grid row at a time: node by node for the
// written-out stencils...
template <typename Taps, typename T>
[[gnu::always_inline]] inline void rowSums(const Taps& taps, const T* center, int length, int s,
                                           T* sum) {
  GEOBRUSH_INDEPENDENT_ITERATIONS
  for (int i = 0; i < length; ++i)
    sum[i] = taps.at(center, i, s);
}

// ...and for 49 weights one stencil row at a time: seven weights and seven streams, in the order
// of WeightTaps::at (several times faster than 49 taps per node).
template <typename T>
[[gnu::always_inline]] inline void rowSums(const WeightTaps<T>& taps, const T* center, int length,
                                           int s, T* sum) {
  if (taps.mirrored) {
    // The rows dy and -dy are added before they are weighted, and so are the columns dx and
    // -dx, which saves a third of the arithmetic.
    const T* a = taps.weights + stencilSlot(0, 0);
    forEachLane<T>(
        length, [&](auto lanes, int i) __attribute__((always_inline)) {
          auto x = [&](int dx) __attribute__((always_inline)) {
            return lanes.load(center + i + dx);
          };
          auto w = [&](int dx) __attribute__((always_inline)) {
            return lanes.splat(a[dx]);
          };
          lanes.store(sum + i, w(0) * x(0) + w(1) * (x(-1) + x(1)) + w(2) * (x(-2) + x(2)) +
                                   w(3) * (x(-3) + x(3)));
        });
    for (int dy = 1; dy <= kReach; ++dy) {
      const T* up = center - dy * s;
      const T* down = center + dy * s;
      const T* b = taps.weights + stencilSlot(0, dy);
      forEachLane<T>(
          length, [&](auto lanes, int i) __attribute__((always_inline)) {
            auto x = [&](int dx) __attribute__((always_inline)) {
              return lanes.load(up + i + dx) + lanes.load(down + i + dx);
            };
            auto w = [&](int dx) __attribute__((always_inline)) {
              return lanes.splat(b[dx]);
            };
            lanes.store(sum + i,
                        lanes.load(sum + i) + (w(0) * x(0) + w(1) * (x(-1) + x(1)) +
                                               w(2) * (x(-2) + x(2)) + w(3) * (x(-3) + x(3))));
          });
    }
    return;
  }
  std::fill(sum, sum + length, T(0));
  for (int dy = -kReach; dy <= kReach; ++dy) {
    const T* row = center + dy * s;
    const T* weights = taps.weights + stencilSlot(0, dy);
    forEachLane<T>(
        length, [&](auto lanes, int i) __attribute__((always_inline)) {
          auto x = [&](int dx) __attribute__((always_inline)) {
            return lanes.load(row + i + dx);
          };
          auto w = [&](int dx) __attribute__((always_inline)) {
            return lanes.splat(weights[dx]);
          };
          lanes.store(sum + i, lanes.load(sum + i) +
                                   (w(-3) * x(-3) + w(-2) * x(-2) + w(-1) * x(-1) + w(0) * x(0) +
                                    w(1) * x(1) + w(2) * x(2) + w(3) * x(3)));
        });
  }
}

// The custom row c's taps: as written in double, padded in float.
inline WeightTaps<double> customTaps(const Level& level, int c, const double*) {
  return {level.customRows[std::size_t(c)].weights.data(), false};
}
inline PaddedTaps customTaps(const Level& level, int c, const float*) {
  return {level.single.customPadded[std::size_t(c)].data()};
}

// Calls body(taps) with the level's regular stencil in precision T; Sweep picks the plate's
// order for Gauss-Seidel sweeps.
template <typename T, bool Sweep = false, typename Body>
[[gnu::always_inline]] inline void withRegularTaps(const Level& level, Body&& body) {
  switch (level.shape) {
    case StencilShape::Plate:
      if constexpr (Sweep)
        body(PlateSweepTaps{});
      else
        body(PlateTaps{});
      return;
    case StencilShape::Laplace:
      body(LaplaceTaps{});
      return;
    case StencilShape::Full:
      body(WeightTaps<T>{Coefficients<T>::regular(level), level.mirrored});
      return;
  }
}

// (A x) at one node: its custom row where it has one, else the regular taps.
template <typename Taps, typename T>
[[gnu::always_inline]] inline T nodeSum(const Level& level, const Taps& regular, const T* x,
                                        int node) {
  const int custom = level.customOfNode[std::size_t(node)];
  if (custom >= 0) return customTaps(level, custom, x).at(x, node, level.grid.stride());
  return regular.at(x, node, level.grid.stride());
}

// The one stencil kernel: (A x)_i over the level's row spans in order, each node's sum handed to
// use(i, sum), and use.rowEnd(begin, end) after each span. A level whose every row is its
// written-out regular stencil (the finest level) sums each node in the loop that uses the sum;
// the others first sum a grid row into a scratch row (rowSums) and patch its custom rows. Every
// node gets the same arithmetic either way. x must not alias what use writes.
template <typename T, typename Use>
void forEachOperatorSum(const Level& level, const T* __restrict x, Use&& use) {
  const int s = level.grid.stride();
  withRegularTaps<T>(
      level, [&](const auto& taps) __attribute__((always_inline)) {
        using Taps = std::decay_t<decltype(taps)>;
        if constexpr (!std::is_same_v<Taps, WeightTaps<T>>) {
          if (level.customRows.empty()) {
            for (const RowSpan& span : level.spans) {
              GEOBRUSH_INDEPENDENT_ITERATIONS
              for (int i = span.begin; i < span.end; ++i)
                use(i, taps.at(x, i, s));
              use.rowEnd(span.begin, span.end);
            }
            return;
          }
        }
        std::vector<T> scratch(std::size_t(level.grid.width));
        T* sums = scratch.data();
        for (int row = 0; row < level.grid.height; ++row) {
          const RowSpan span = level.spans[std::size_t(row)];
          const int length = span.end - span.begin;
          if (length == 0) continue;
          rowSums(taps, x + span.begin, length, s, sums);
          for (int c = level.customBegin[std::size_t(row)];
               c < level.customBegin[std::size_t(row) + 1]; ++c) {
            const int node = level.customRows[std::size_t(c)].node;
            sums[node - span.begin] = customTaps(level, c, x).at(x, node, s);
          }
          GEOBRUSH_INDEPENDENT_ITERATIONS
          for (int i = 0; i < length; ++i)
            use(span.begin + i, sums[i]);
          use.rowEnd(span.begin, span.end);
        }
      });
}

// A use of forEachOperatorSum that needs nothing at the end of a row.
template <typename PerNode>
struct NodeUse {
  PerNode perNode;
  [[gnu::always_inline]] void operator()(int i, auto sum) { perNode(i, sum); }
  void rowEnd(int, int) {}
};
template <typename PerNode>
NodeUse(PerNode) -> NodeUse<PerNode>;

template <typename T>
void applyOperatorRows(const Level& level, const T* x, T* out) {
  const T* mask = Coefficients<T>::mask(level);
  forEachOperatorSum(level, x, NodeUse{[&](int i, T sum) { out[i] = mask[i] * sum; }});
}

// out may alias base: each node reads base before it writes out.
template <typename T>
void subtractOperatorRows(const Level& level, const T* base, const T* x, T* out) {
  const T* mask = Coefficients<T>::mask(level);
  forEachOperatorSum(level, x, NodeUse{[&](int i, T sum) { out[i] = mask[i] * (base[i] - sum); }});
}

// inverseDiagonal is 0 off the unknowns, which keeps d and xNext at 0 there.
void chebyshevStepRows(const Level& level, const float* b, const float* x, float* xNext, float* d,
                       float keep, float gain) {
  const float* inverseDiagonal = level.single.inverseDiagonal.data();
  forEachOperatorSum(level, x, NodeUse{[&](int i, float sum) {
                       d[i] = keep * d[i] + gain * inverseDiagonal[i] * (b[i] - sum);
                       xNext[i] = x[i] + d[i];
                     }});
}

template <typename T>
T rowProductAt(const Level& level, const T* x, int node) {
  T sum = 0;
  withRegularTaps<T>(
      level, [&](const auto& taps)
                 __attribute__((always_inline)) { sum = nodeSum(level, taps, x, node); });
  return sum;
}

// The largest Ritz value of D^-1/2 A D^-1/2 after a few Lanczos steps: from below, within a few
// percent of lambda_max(D^-1 A). Gershgorin's bound, exact on the finest level, is several times
// too large on coarse levels whose rows near the boundary of Q have large off-diagonal weights;
// a Chebyshev smoother tuned to it would leave half of the spectrum undamped.
double largestRitzValue(const Level& level) {
  constexpr int kSteps = 8;
  // In float, as the cycle runs: an estimate a few percent low is all that is needed.
  const std::size_t size = level.grid.size();
  const std::size_t begin = std::size_t(level.activeBegin), end = std::size_t(level.activeEnd);
  std::vector<float> scale(size, 0.0f), q(size, 0.0f), previous(size, 0.0f), w(size, 0.0f),
      scaled(size, 0.0f);
  for (int node : level.unknowns)
    scale[std::size_t(node)] = float(std::sqrt(level.inverseDiagonal[std::size_t(node)]));
  // A fixed pseudo-random start: deterministic, and with components along every eigenvector.
  std::uint32_t state = 12345;
  for (int node : level.unknowns) {
    state = state * 1664525u + 1013904223u;
    q[std::size_t(node)] = float(double(state >> 8) / double(1u << 24) - 0.5);
  }
  // Four interleaved sums in double: vectorizable, and the same order on every run.
  auto dot = [&](const std::vector<float>& a, const std::vector<float>& b) {
    std::array<double, 4> sums{};
    std::size_t i = begin;
    for (; i + 4 <= end; i += 4)
      for (std::size_t k = 0; k < 4; ++k)
        sums[k] += double(a[i + k]) * double(b[i + k]);
    for (; i < end; ++i)
      sums[0] += double(a[i]) * double(b[i]);
    return (sums[0] + sums[1]) + (sums[2] + sums[3]);
  };
  const double start = std::sqrt(dot(q, q));
  if (start == 0) return 0;
  for (std::size_t i = begin; i < end; ++i)
    q[i] = float(q[i] / start);
  std::vector<double> alphas, betas;
  double beta = 0;
  for (int step = 0; step < kSteps; ++step) {
    for (std::size_t i = begin; i < end; ++i)
      scaled[i] = scale[i] * q[i];
    applyOperator(level, scaled.data(), w.data());
    const float previousWeight = float(beta);
    for (std::size_t i = begin; i < end; ++i)
      w[i] = scale[i] * w[i] - previousWeight * previous[i];
    const double alpha = dot(w, q);
    for (std::size_t i = begin; i < end; ++i)
      w[i] -= float(alpha) * q[i];
    alphas.push_back(alpha);
    beta = std::sqrt(dot(w, w));
    if (beta <= 1e-6 * std::abs(alpha)) break;  // an invariant subspace: the Ritz values are exact
    betas.push_back(beta);
    for (std::size_t i = begin; i < end; ++i) {
      previous[i] = q[i];
      q[i] = float(w[i] / beta);
    }
  }
  const auto k = Eigen::Index(alphas.size());
  Eigen::VectorXd diagonal = Eigen::Map<const Eigen::VectorXd>(alphas.data(), k);
  Eigen::VectorXd subdiagonal = Eigen::Map<const Eigen::VectorXd>(betas.data(), k - 1);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tridiagonal;
  tridiagonal.computeFromTridiagonal(diagonal, subdiagonal, Eigen::EigenvaluesOnly);
  return tridiagonal.eigenvalues().maxCoeff();
}

template <typename T>
void restrictRows(const Level& fine, const Level& coarse, const T* fineValues, T* coarseValues) {
  std::vector<T> columnSums(std::size_t(fine.grid.stride()));
  const T* coarseMask = Coefficients<T>::mask(coarse);
  for (int y = 0; y < coarse.grid.height; ++y) {
    const RowSpan span = coarse.spans[std::size_t(y)];
    if (span.begin == span.end) continue;
    const int rowStart = coarse.grid.index(0, y);
    const int firstX = fineOf(span.begin - rowStart) - kSplineReach;
    const int lastX = fineOf(span.end - 1 - rowStart) + kSplineReach;
    // Along y first: columnSums[x - firstX] = sum over dy of w(dy) fine(x, fineOf(y) + dy).
    std::fill(columnSums.begin(), columnSums.end(), T(0));
    for (int dy = -kSplineReach; dy <= kSplineReach; ++dy) {
      const T weight = T(splineWeight(dy));
      const T* fineRow = fineValues + fine.grid.index(firstX, fineOf(y) + dy);
      for (int x = 0; x <= lastX - firstX; ++x)
        columnSums[std::size_t(x)] += weight * fineRow[x];
    }
    for (int node = span.begin; node < span.end; ++node) {
      const T* sums = columnSums.data() + (fineOf(node - rowStart) - firstX);
      const T value =
          T(0.125) * (sums[-2] + sums[2]) + T(0.5) * (sums[-1] + sums[1]) + T(0.75) * sums[0];
      coarseValues[node] = coarseMask[node] * value;
    }
  }
}

template <typename T>
void prolongRows(const Level& coarse, const Level& fine, const T* coarseValues, T* fineValues) {
  std::vector<T> rowMix(std::size_t(coarse.grid.stride()));
  std::vector<T> line(std::size_t(fine.grid.stride()) + 2);
  const T* fineMask = Coefficients<T>::mask(fine);
  for (int y = 0; y < fine.grid.height; ++y) {
    const RowSpan span = fine.spans[std::size_t(y)];
    if (span.begin == span.end) continue;
    const int rowStart = fine.grid.index(0, y);
    const int firstX = span.begin - rowStart, lastX = span.end - 1 - rowStart;
    // The coarse columns that reach fine columns firstX..lastX. Coarse row (y + 2) / 2 lies on
    // an even y; an odd y lies between it and the next.
    const int firstColumn = firstX / 2, lastColumn = lastX / 2 + 2;
    // Along y first: rowMix[X - firstColumn] mixes the coarse rows around y.
    const T* row = coarseValues + coarse.grid.index(firstColumn, (y + 2) / 2);
    const int stride = coarse.grid.stride();
    for (int column = 0; column <= lastColumn - firstColumn; ++column) {
      const T* c = row + column;
      rowMix[std::size_t(column)] = y % 2 == 0
                                        ? T(0.125) * (c[-stride] + c[stride]) + T(0.75) * c[0]
                                        : T(0.5) * (c[0] + c[stride]);
    }
    // Even x lies on coarse column (x + 2) / 2, odd x between that one and the next: the fine
    // columns from the even firstEven = 2 firstColumn on, in pairs, then added under the mask
    // (0 off the unknowns, where the value is 0 and stays so). Branch-free, so both loops
    // vectorize.
    const int firstEven = 2 * firstColumn;
    const int pairs = (lastX - firstEven) / 2 + 1;
    const T* m = rowMix.data();
    for (int j = 0; j < pairs; ++j) {
      line[std::size_t(2 * j)] = T(0.125) * (m[j] + m[j + 2]) + T(0.75) * m[j + 1];
      line[std::size_t(2 * j + 1)] = T(0.5) * (m[j + 1] + m[j + 2]);
    }
    const T* values = line.data() - firstEven;
    for (int x = firstX; x <= lastX; ++x)
      fineValues[rowStart + x] += fineMask[rowStart + x] * values[x];
  }
}

// Adds a[i] b[i] for i in [begin, end) to four interleaved sums, the first at begin.
[[gnu::always_inline]] inline void addProducts(const double* a, const double* b, int begin, int end,
                                               std::array<double, 4>& sums) {
  int i = begin;
  for (; i + 4 <= end; i += 4)
    for (int k = 0; k < 4; ++k)
      sums[std::size_t(k)] += a[i + k] * b[i + k];
  for (int k = 0; i < end; ++i, ++k)
    sums[std::size_t(k)] += a[i] * b[i];
}

double total(const std::array<double, 4>& sums) {
  return (sums[0] + sums[1]) + (sums[2] + sums[3]);
}

double dotProductRows(const Level& level, const double* a, const double* b) {
  std::array<double, 4> sums{};
  for (const RowSpan& span : level.spans)
    addProducts(a, b, span.begin, span.end, sums);
  return total(sums);
}

double applyOperatorDotRows(const Level& level, const double* p, double* q) {
  struct Use {
    const double* mask;
    const double* p;
    double* q;
    std::array<double, 4> sums{};
    [[gnu::always_inline]] void operator()(int i, double sum) { q[i] = mask[i] * sum; }
    void rowEnd(int begin, int end) { addProducts(p, q, begin, end, sums); }
  } use{level.mask.data(), p, q};
  forEachOperatorSum(level, p, use);
  return total(use.sums);
}

double updateResidualRows(const Level& level, double alpha, const double* p, const double* q,
                          double* x, double* r) {
  std::array<double, 4> sums{};
  for (const RowSpan& span : level.spans) {
    for (int i = span.begin; i < span.end; ++i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
    }
    addProducts(r, r, span.begin, span.end, sums);
  }
  return total(sums);
}

void sweepBandNodes(const Level& level, const float* b, float* x, bool forward, int sweeps) {
  const float* inverseDiagonal = level.single.inverseDiagonal.data();
  const int* band = level.band.data();
  const int count = int(level.band.size());
  withRegularTaps<float, true>(
      level, [&](const auto& taps) __attribute__((always_inline)) {
        for (int sweep = 0; sweep < sweeps; ++sweep)
          for (int k = 0; k < count; ++k) {
            const int node = band[forward ? k : count - 1 - k];
            x[node] += (b[node] - nodeSum(level, taps, x, node)) * inverseDiagonal[node];
          }
      });
}

}  // namespace

// The exported kernels in both precisions.
void applyOperator(const Level& level, const double* x, double* out) {
  simd::fastest([&] { applyOperatorRows(level, x, out); });
}
void applyOperator(const Level& level, const float* x, float* out) {
  simd::fastest([&] { applyOperatorRows(level, x, out); });
}
void subtractOperator(const Level& level, const double* base, const double* x, double* out) {
  simd::fastest([&] { subtractOperatorRows(level, base, x, out); });
}
void subtractOperator(const Level& level, const float* base, const float* x, float* out) {
  simd::fastest([&] { subtractOperatorRows(level, base, x, out); });
}
void chebyshevStep(const Level& level, const float* b, const float* x, float* xNext, float* d,
                   float keep, float gain) {
  simd::fastest([&] { chebyshevStepRows(level, b, x, xNext, d, keep, gain); });
}
double dotProduct(const Level& level, const double* a, const double* b) {
  return simd::fastest([&] { return dotProductRows(level, a, b); });
}
double applyOperatorDot(const Level& level, const double* p, double* q) {
  return simd::fastest([&] { return applyOperatorDotRows(level, p, q); });
}
double updateResidual(const Level& level, double alpha, const double* p, const double* q, double* x,
                      double* r) {
  return simd::fastest([&] { return updateResidualRows(level, alpha, p, q, x, r); });
}
double rowProduct(const Level& level, const double* x, int node) {
  return rowProductAt(level, x, node);
}
float rowProduct(const Level& level, const float* x, int node) {
  return rowProductAt(level, x, node);
}
void sweepBand(const Level& level, const float* b, float* x, bool forward, int sweeps) {
  simd::fastest([&] { sweepBandNodes(level, b, x, forward, sweeps); });
}
void restrictToCoarse(const Level& fine, const Level& coarse, const double* fineValues,
                      double* coarseValues) {
  simd::fastest([&] { restrictRows(fine, coarse, fineValues, coarseValues); });
}
void restrictToCoarse(const Level& fine, const Level& coarse, const float* fineValues,
                      float* coarseValues) {
  simd::fastest([&] { restrictRows(fine, coarse, fineValues, coarseValues); });
}
void prolongAdd(const Level& coarse, const Level& fine, const double* coarseValues,
                double* fineValues) {
  simd::fastest([&] { prolongRows(coarse, fine, coarseValues, fineValues); });
}
void prolongAdd(const Level& coarse, const Level& fine, const float* coarseValues,
                float* fineValues) {
  simd::fastest([&] { prolongRows(coarse, fine, coarseValues, fineValues); });
}

Level finestLevel(int width, int height, const std::vector<std::uint8_t>& inside,
                  MembraneContinuity continuity, int bandWidth) {
  Level level;
  level.grid = {width, height};
  level.mask.assign(level.grid.size(), 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      if (inside[std::size_t(y) * std::size_t(width) + std::size_t(x)])
        level.mask[std::size_t(level.grid.index(x, y))] = 1;
  const bool plate = continuity == MembraneContinuity::C1;
  level.regular = plate ? plateStencil() : laplaceStencil();
  level.shape = plate ? StencilShape::Plate : StencilShape::Laplace;
  level.reach = plate ? 2 : 1;
  finishLevel(level, bandWidth);
  return level;
}

Level coarsenLevel(const Level& fine, int bandWidth, const Level* previous,
                   const std::vector<std::uint8_t>* fineChanged, int threads) {
  const PaddedGrid& fineGrid = fine.grid;
  Level coarse;
  coarse.grid = {fineGrid.width / 2 + 3, fineGrid.height / 2 + 3};
  coarse.regular = galerkinStencil(fine.regular);
  coarse.shape = StencilShape::Full;
  coarse.reach = kReach;

  std::vector<std::uint8_t> unknown(fineGrid.size()), irregular(fineGrid.size());
  for (std::size_t i = 0; i < unknown.size(); ++i) {
    unknown[i] = fine.mask[i] != 0;
    irregular[i] = !unknown[i] || fine.customOfNode[i] >= 0;
  }
  // A coarse node is unknown when its B-spline covers a fine unknown; its row is the regular
  // Galerkin stencil when every fine node that R A P reads for it is an unknown with a regular
  // row. The same window bounds what a change of the fine level can reach.
  const int window = kSplineReach + fine.reach;
  const std::vector<std::uint8_t> coversUnknown = dilate(fineGrid, unknown, kSplineReach);
  const std::vector<std::uint8_t> nearIrregular = dilate(fineGrid, irregular, window);
  const std::vector<std::uint8_t> reachedByChange =
      previous ? dilate(fineGrid, *fineChanged, window) : std::vector<std::uint8_t>();

  coarse.mask.assign(coarse.grid.size(), 0);
  // Each grid row's custom rows on its own, joined in row order below: the same for any number
  // of threads. Small levels stay on one: starting a thread costs more than their rows.
  std::vector<std::vector<CustomRow>> customOfRow(std::size_t(coarse.grid.height));
  constexpr std::size_t kRowsPerBlock = 4;
  constexpr std::size_t kUnknownsPerThread = 4096;
  const int rowThreads = fine.unknowns.size() < kUnknownsPerThread ? 1 : threads;
  parallelBlocks(std::size_t(coarse.grid.height), kRowsPerBlock, rowThreads,
                 [&](std::size_t firstRow, std::size_t lastRow) {
                   for (int y = int(firstRow); y < int(lastRow); ++y) {
                     std::vector<CustomRow>& custom = customOfRow[std::size_t(y)];
                     for (int x = 0; x < coarse.grid.width; ++x) {
                       const std::size_t f = std::size_t(fineGrid.index(fineOf(x), fineOf(y)));
                       if (!coversUnknown[f]) continue;
                       const int node = coarse.grid.index(x, y);
                       coarse.mask[std::size_t(node)] = 1;
                       if (!nearIrregular[f]) continue;
                       if (previous && !reachedByChange[f]) {
                         // The window is as it was: so is the row.
                         const int c = previous->customOfNode[std::size_t(node)];
                         if (c >= 0) custom.push_back(previous->customRows[std::size_t(c)]);
                         continue;
                       }
                       // Near the boundary most rows differ from the regular stencil, some do not.
                       const Stencil row = galerkinRow(fine, x, y);
                       if (row != coarse.regular) custom.push_back({node, row});
                     }
                   }
                 });
  std::size_t customCount = 0;
  for (const std::vector<CustomRow>& rows : customOfRow)
    customCount += rows.size();
  coarse.customRows.reserve(customCount);
  for (const std::vector<CustomRow>& rows : customOfRow)
    coarse.customRows.insert(coarse.customRows.end(), rows.begin(), rows.end());
  finishLevel(coarse, bandWidth);
  coarse.lambdaMax = std::min(coarse.lambdaMax, kLanczosSafety * largestRitzValue(coarse));
  return coarse;
}

std::vector<std::uint8_t> changedNodes(const Level& now, const Level& before) {
  std::vector<std::uint8_t> changed(now.grid.size(), 0);
  for (std::size_t i = 0; i < changed.size(); ++i) {
    if (now.mask[i] != before.mask[i]) {
      changed[i] = 1;
    } else if (now.customOfNode[i] >= 0 || before.customOfNode[i] >= 0) {
      changed[i] = rowWeights(now, int(i)) != rowWeights(before, int(i));
    }
  }
  return changed;
}

CoarsestSolver factorCoarsest(const Level& level) {
  CoarsestSolver solver;
  solver.nodes = level.unknowns;
  const int n = int(solver.nodes.size());
  std::vector<int> position(level.grid.size(), -1);
  for (int i = 0; i < n; ++i)
    position[std::size_t(solver.nodes[std::size_t(i)])] = i;
  Eigen::MatrixXd matrix = Eigen::MatrixXd::Zero(n, n);
  const int stride = level.grid.stride();
  for (int i = 0; i < n; ++i) {
    const int node = solver.nodes[std::size_t(i)];
    const Stencil& w = rowWeights(level, node);
    for (int dy = -kReach; dy <= kReach; ++dy)
      for (int dx = -kReach; dx <= kReach; ++dx) {
        const int j = position[std::size_t(node + dy * stride + dx)];
        if (j >= 0) matrix(i, j) += w[stencilSlot(dx, dy)];
      }
  }
  solver.factorization.compute(matrix);
  const double largestPivot = n > 0 ? solver.factorization.vectorD().cwiseAbs().maxCoeff() : 0;
  solver.pivotTolerance = 1e-12 * largestPivot;
  return solver;
}

void solveCoarsest(const CoarsestSolver& solver, const float* b, float* x,
                   Eigen::VectorXd& scratch) {
  const auto n = Eigen::Index(solver.nodes.size());
  scratch.resize(n);
  for (Eigen::Index i = 0; i < n; ++i)
    scratch[i] = b[solver.nodes[std::size_t(i)]];
  const auto& ldlt = solver.factorization;
  scratch = ldlt.transpositionsP() * scratch;
  ldlt.matrixL().solveInPlace(scratch);
  const Eigen::VectorXd& pivots = ldlt.vectorD();
  for (Eigen::Index i = 0; i < n; ++i)
    scratch[i] = std::abs(pivots[i]) > solver.pivotTolerance ? scratch[i] / pivots[i] : 0.0;
  ldlt.matrixU().solveInPlace(scratch);
  scratch = ldlt.transpositionsP().transpose() * scratch;
  for (Eigen::Index i = 0; i < n; ++i)
    x[solver.nodes[std::size_t(i)]] = float(scratch[i]);
}

}  // namespace geobrush::membrane_detail

namespace geobrush {

MembraneHierarchy::MembraneHierarchy(int width, int height, std::vector<std::uint8_t> inside,
                                     MembraneContinuity continuity,
                                     const MembraneMultigridSettings& settings,
                                     const MembraneHierarchy* previous, int threads)
    : width_(width),
      height_(height),
      inside_(std::move(inside)),
      continuity_(continuity),
      bandWidth_(settings.bandWidth),
      coarsestUnknowns_(settings.coarsestUnknowns) {
  for (auto& flag : inside_)
    flag = flag != 0;
  levels_.push_back(
      membrane_detail::finestLevel(width_, height_, inside_, continuity_, bandWidth_));
  // A region of scattered single nodes may gain unknowns on a coarser level, but never more than
  // the shrinking grid holds: a coarse grid is smaller than its fine grid down to 6 x 6.
  auto canShrink = [](const membrane_detail::Level& level) {
    return level.grid.width > 6 || level.grid.height > 6;
  };
  const bool related = previous && previous->width_ == width_ && previous->height_ == height_ &&
                       previous->continuity_ == continuity_ && previous->bandWidth_ == bandWidth_;
  while (levels_.back().unknowns.size() > std::size_t(coarsestUnknowns_) &&
         canShrink(levels_.back())) {
    // Levels of a previous region on the same grid lie on the same grids: rows that its change
    // cannot reach are copied instead of recomputed.
    const std::size_t fine = levels_.size() - 1;
    if (related && fine + 1 < previous->levels_.size()) {
      const std::vector<std::uint8_t> changed =
          membrane_detail::changedNodes(levels_[fine], previous->levels_[fine]);
      levels_.push_back(membrane_detail::coarsenLevel(
          levels_[fine], bandWidth_, &previous->levels_[fine + 1], &changed, threads));
    } else {
      levels_.push_back(
          membrane_detail::coarsenLevel(levels_[fine], bandWidth_, nullptr, nullptr, threads));
    }
  }
  coarsest_ = membrane_detail::factorCoarsest(levels_.back());
}

bool MembraneHierarchy::fits(const MembraneProblem& problem,
                             const MembraneMultigridSettings& settings) const {
  if (problem.width != width_ || problem.height != height_ || problem.continuity != continuity_ ||
      settings.bandWidth != bandWidth_ || settings.coarsestUnknowns != coarsestUnknowns_ ||
      problem.inside.size() != inside_.size())
    return false;
  for (std::size_t i = 0; i < inside_.size(); ++i)
    if ((problem.inside[i] != 0) != (inside_[i] != 0)) return false;
  return true;
}

}  // namespace geobrush
