#include "geobrush/loop_zip.hpp"

#include <limits>

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

}  // namespace

bool DomainZipMetric::turnsOver(LoopCorner p, LoopCorner q, LoopCorner r) const {
  const Eigen::Vector2d e = at(q) - at(p), f = at(r) - at(p);
  return e.x() * f.y() - e.y() * f.x() < 0;
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

}  // namespace geobrush
