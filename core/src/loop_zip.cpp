#include "geobrush/loop_zip.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Geometry>

namespace geobrush {
namespace {

// A strip is the steps of a walk along a forwards and b backwards from a[0] and b[start]; true
// advances along a.
using Strip = std::vector<char>;

struct StripWalk {
  const LoopZipMetric& metric;
  std::size_t na, nb, start;
  std::size_t aAt(std::size_t step) const { return step % na; }
  std::size_t bAt(std::size_t step) const { return (start + nb - step % nb) % nb; }
  // The step from (i, j) along a: triangle a_i, a_i+1, b_j.
  bool turnsAlongA(std::size_t i, std::size_t j) const {
    return metric.turnsOver({true, aAt(i)}, {true, aAt(i + 1)}, {false, bAt(j)});
  }
  // The step from (i, j) along b: triangle b_j+1, b_j, a_i.
  bool turnsAlongB(std::size_t i, std::size_t j) const {
    return metric.turnsOver({false, bAt(j + 1)}, {false, bAt(j)}, {true, aAt(i)});
  }
  double crossEdge(std::size_t i, std::size_t j) const { return metric.edge(aAt(i), bAt(j)); }
};

Strip greedyStrip(const StripWalk& walk, bool keepOrientation) {
  Strip strip;
  std::size_t i = 0, j = 0;
  while (i < walk.na || j < walk.nb) {
    bool alongA =
        j == walk.nb || (i < walk.na && walk.crossEdge(i + 1, j) <= walk.crossEdge(i, j + 1));
    if (keepOrientation && i < walk.na && j < walk.nb) {
      const bool aTurns = walk.turnsAlongA(i, j), bTurns = walk.turnsAlongB(i, j);
      if (aTurns != bTurns) alongA = bTurns;
    }
    strip.push_back(alongA);
    (alongA ? i : j) += 1;
  }
  return strip;
}

std::size_t turnedOver(const StripWalk& walk, const Strip& strip) {
  std::size_t turned = 0, i = 0, j = 0;
  for (const char alongA : strip) {
    turned += alongA ? walk.turnsAlongA(i, j) : walk.turnsAlongB(i, j);
    (alongA ? i : j) += 1;
  }
  return turned;
}

// A shortest path through the grid of (steps along a, steps along b), turned-over triangles
// counted first, then the sum of new edges.
Strip fewestTurnedStrip(const StripWalk& walk) {
  const std::size_t na = walk.na, nb = walk.nb, columns = nb + 1;
  struct Cost {
    std::size_t turned = std::numeric_limits<std::size_t>::max();
    double length = std::numeric_limits<double>::infinity();
    bool operator<(const Cost& other) const {
      return turned != other.turned ? turned < other.turned : length < other.length;
    }
  };
  std::vector<Cost> best((na + 1) * columns);
  std::vector<char> cameAlongA((na + 1) * columns, 0);
  best[0] = {0, 0};
  for (std::size_t i = 0; i <= na; ++i)
    for (std::size_t j = 0; j <= nb; ++j) {
      if (i == 0 && j == 0) continue;
      const double edge = walk.crossEdge(i, j);
      Cost cost;
      if (i > 0) {
        const Cost& before = best[(i - 1) * columns + j];
        cost = {before.turned + walk.turnsAlongA(i - 1, j), before.length + edge};
        cameAlongA[i * columns + j] = 1;
      }
      if (j > 0) {
        const Cost& before = best[i * columns + j - 1];
        const Cost alongB{before.turned + walk.turnsAlongB(i, j - 1), before.length + edge};
        if (alongB < cost) {
          cost = alongB;
          cameAlongA[i * columns + j] = 0;
        }
      }
      best[i * columns + j] = cost;
    }
  Strip strip(na + nb);
  for (std::size_t i = na, j = nb, k = na + nb; k-- > 0;) {
    strip[k] = cameAlongA[i * columns + j];
    (strip[k] ? i : j) -= 1;
  }
  return strip;
}

// Loops longer than this product are left to the greedy strip.
constexpr std::size_t kMaxStripGrid = std::size_t(1) << 22;

// A triangle whose height is below this share of its longest side lies flat.
constexpr double kFlatHeight = 1e-9;

// A walk from a_0 (= b_q) to a_p (= b_0): state (i, j) joins a_i and b_(q - j), j counting steps
// back along b.
struct ChainWalk {
  const std::vector<int>& a;
  const std::vector<int>& b;
  const LoopZipMetric& metric;
  std::size_t p() const { return a.size() - 1; }
  std::size_t q() const { return b.size() - 1; }
  std::size_t bAt(std::size_t j) const { return q() - j; }
  // States other than the start and the end that would join a vertex to itself (with one shared
  // vertex, the corners where one chain is done before the other started).
  bool blocked(std::size_t i, std::size_t j) const {
    const bool startOrEnd = (i == 0 && j == 0) || (i == p() && j == q());
    return !startOrEnd && a[i] == b[bAt(j)];
  }
  // The step from (i, j) along a: triangle a_i, a_i+1, b_(q-j); along b: b_(q-j-1), b_(q-j), a_i.
  std::array<LoopCorner, 3> step(std::size_t i, std::size_t j, bool alongA) const {
    if (alongA) return {LoopCorner{true, i}, LoopCorner{true, i + 1}, LoopCorner{false, bAt(j)}};
    return {LoopCorner{false, bAt(j) - 1}, LoopCorner{false, bAt(j)}, LoopCorner{true, i}};
  }
  int id(LoopCorner c) const { return c.onA ? a[c.index] : b[c.index]; }
  // The first and last steps join a vertex to itself: no triangle.
  bool degenerate(const std::array<LoopCorner, 3>& t) const {
    return id(t[0]) == id(t[1]) || id(t[1]) == id(t[2]) || id(t[2]) == id(t[0]);
  }
  bool bad(std::size_t i, std::size_t j, bool alongA) const {
    const auto t = step(i, j, alongA);
    return !degenerate(t) && (metric.turnsOver(t[0], t[1], t[2]) || metric.flat(t[0], t[1], t[2]));
  }
  double crossEdge(std::size_t i, std::size_t j) const { return metric.edge(i, bAt(j)); }
};

// Empty when the walk cannot reach the end (never for chains of two or more vertices).
Strip greedyChainStrip(const ChainWalk& walk, bool keepOrientation) {
  Strip strip;
  std::size_t i = 0, j = 0;
  while (i < walk.p() || j < walk.q()) {
    const bool canA = i < walk.p() && !walk.blocked(i + 1, j);
    const bool canB = j < walk.q() && !walk.blocked(i, j + 1);
    if (!canA && !canB) return {};
    bool alongA = canA && (!canB || walk.crossEdge(i + 1, j) <= walk.crossEdge(i, j + 1));
    if (keepOrientation && canA && canB) {
      const bool aBad = walk.bad(i, j, true), bBad = walk.bad(i, j, false);
      if (aBad != bBad) alongA = bBad;
    }
    strip.push_back(alongA);
    (alongA ? i : j) += 1;
  }
  return strip;
}

std::size_t badSteps(const ChainWalk& walk, const Strip& strip) {
  std::size_t count = 0, i = 0, j = 0;
  for (const char alongA : strip) {
    count += walk.bad(i, j, alongA);
    (alongA ? i : j) += 1;
  }
  return count;
}

// A shortest path through the grid of states avoiding the blocked ones, turned-over and flat
// triangles counted first, then the sum of new edges.
Strip fewestBadChainStrip(const ChainWalk& walk) {
  const std::size_t p = walk.p(), q = walk.q(), columns = q + 1;
  struct Cost {
    std::size_t bad = std::numeric_limits<std::size_t>::max();
    double length = std::numeric_limits<double>::infinity();
    bool operator<(const Cost& other) const {
      return bad != other.bad ? bad < other.bad : length < other.length;
    }
  };
  std::vector<Cost> best((p + 1) * columns);
  std::vector<char> cameAlongA((p + 1) * columns, 0);
  best[0] = {0, 0};
  for (std::size_t i = 0; i <= p; ++i)
    for (std::size_t j = 0; j <= q; ++j) {
      if ((i == 0 && j == 0) || walk.blocked(i, j)) continue;
      const double edge = walk.crossEdge(i, j);
      Cost cost;
      if (i > 0 && best[(i - 1) * columns + j].length < std::numeric_limits<double>::infinity()) {
        const Cost& before = best[(i - 1) * columns + j];
        cost = {before.bad + walk.bad(i - 1, j, true), before.length + edge};
        cameAlongA[i * columns + j] = 1;
      }
      if (j > 0 && best[i * columns + j - 1].length < std::numeric_limits<double>::infinity()) {
        const Cost& before = best[i * columns + j - 1];
        const Cost alongB{before.bad + walk.bad(i, j - 1, false), before.length + edge};
        if (alongB < cost) {
          cost = alongB;
          cameAlongA[i * columns + j] = 0;
        }
      }
      best[i * columns + j] = cost;
    }
  Strip strip(p + q);
  for (std::size_t i = p, j = q, k = p + q; k-- > 0;) {
    strip[k] = cameAlongA[i * columns + j];
    (strip[k] ? i : j) -= 1;
  }
  return strip;
}

}  // namespace

bool DomainZipMetric::turnsOver(LoopCorner p, LoopCorner q, LoopCorner r) const {
  const Eigen::Vector2d e = at(q) - at(p), f = at(r) - at(p);
  return e.x() * f.y() - e.y() * f.x() < 0;
}

bool DomainZipMetric::flat(LoopCorner p, LoopCorner q, LoopCorner r) const {
  const Eigen::Vector2d e = at(q) - at(p), f = at(r) - at(p), g = at(r) - at(q);
  const double longest = std::max({e.squaredNorm(), f.squaredNorm(), g.squaredNorm()});
  return std::abs(e.x() * f.y() - e.y() * f.x()) <= kFlatHeight * longest;
}

bool SpaceZipMetric::flat(LoopCorner p, LoopCorner q, LoopCorner r) const {
  const Eigen::Vector3d e = pointAt(q) - pointAt(p), f = pointAt(r) - pointAt(p),
                        g = pointAt(r) - pointAt(q);
  const double longest = std::max({e.squaredNorm(), f.squaredNorm(), g.squaredNorm()});
  return e.cross(f).norm() <= kFlatHeight * longest;
}

bool SpaceZipMetric::turnsOver(LoopCorner p, LoopCorner q, LoopCorner r) const {
  auto point = [&](LoopCorner c) { return c.onA ? pointsA_[c.index] : pointsB_[c.index]; };
  auto normal = [&](LoopCorner c) { return c.onA ? normalsA_[c.index] : normalsB_[c.index]; };
  const Eigen::Vector3d n = (point(q) - point(p)).cross(point(r) - point(p));
  return n.dot(normal(p) + normal(q) + normal(r)) < 0;
}

std::vector<std::array<int, 3>> zipLoops(const std::vector<int>& a, const std::vector<int>& b,
                                         const LoopZipMetric& metric, bool keepOrientation) {
  std::size_t start = 0;
  double nearest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < b.size(); ++k) {
    const double d = metric.edge(0, k);
    if (d < nearest) {
      nearest = d;
      start = k;
    }
  }
  const StripWalk walk{metric, a.size(), b.size(), start};
  Strip strip = greedyStrip(walk, keepOrientation);
  const std::size_t greedyTurned = turnedOver(walk, strip);
  if (greedyTurned > 0 && (a.size() + 1) * (b.size() + 1) <= kMaxStripGrid) {
    Strip fewest = fewestTurnedStrip(walk);
    if (turnedOver(walk, fewest) < greedyTurned) strip = std::move(fewest);
  }
  std::vector<std::array<int, 3>> triangles;
  triangles.reserve(strip.size());
  std::size_t i = 0, j = 0;
  for (const char alongA : strip) {
    if (alongA) {
      triangles.push_back({a[walk.aAt(i)], a[walk.aAt(i + 1)], b[walk.bAt(j)]});
      ++i;
    } else {
      triangles.push_back({b[walk.bAt(j + 1)], b[walk.bAt(j)], a[walk.aAt(i)]});
      ++j;
    }
  }
  return triangles;
}

std::vector<std::array<int, 3>> zipChains(const std::vector<int>& a, const std::vector<int>& b,
                                          const LoopZipMetric& metric, bool keepOrientation) {
  if (a.size() < 2 || b.size() < 2)
    throw std::invalid_argument("a chain to zip needs at least two vertices");
  if (a.front() != b.back() || a.back() != b.front())
    throw std::invalid_argument("the chains to zip do not share their ends");
  const ChainWalk walk{a, b, metric};
  Strip strip = greedyChainStrip(walk, keepOrientation);
  const std::size_t greedyBad = strip.empty() ? a.size() + b.size() : badSteps(walk, strip);
  if (greedyBad > 0 && a.size() * b.size() <= kMaxStripGrid) {
    Strip fewest = fewestBadChainStrip(walk);
    if (strip.empty() || badSteps(walk, fewest) < greedyBad) strip = std::move(fewest);
  }
  if (strip.empty()) throw std::invalid_argument("the chains cannot be zipped");
  std::vector<std::array<int, 3>> triangles;
  std::size_t i = 0, j = 0;
  for (const char alongA : strip) {
    const auto t = walk.step(i, j, alongA);
    if (!walk.degenerate(t)) triangles.push_back({walk.id(t[0]), walk.id(t[1]), walk.id(t[2])});
    (alongA ? i : j) += 1;
  }
  return triangles;
}

}  // namespace geobrush
