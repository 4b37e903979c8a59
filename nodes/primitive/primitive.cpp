#include "primitive.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iomanip>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace geobrush {
namespace {

using Vec3d = OpenMesh::Vec3d;
using Triangle = std::array<int, 3>;

// The base shape before relief: exact points, their exact unit normals, and the triangles.
struct Surface {
  std::vector<Vec3d> points;
  std::vector<Vec3d> normals;
  std::vector<Triangle> triangles;
};

void report(const PrimitiveOptions& options, double fraction) {
  if (options.progress) options.progress(fraction);
}

// Splits the quad a-b-c-d (counter-clockwise seen from outside) along its shorter diagonal,
// which keeps the smallest angle large on sheared quads. Near-ties take a-c, so that square
// grids get one regular diagonal direction instead of a pattern decided by rounding.
void addQuad(Surface& s, int a, int b, int c, int d) {
  const double ac = (s.points[a] - s.points[c]).sqrnorm();
  const double bd = (s.points[b] - s.points[d]).sqrnorm();
  if (bd < ac * (1.0 - 1e-9)) {
    s.triangles.push_back({a, b, d});
    s.triangles.push_back({b, c, d});
  } else {
    s.triangles.push_back({a, b, c});
    s.triangles.push_back({a, c, d});
  }
}

// Gives every lattice key one vertex index, in order of first use, so that points shared by
// several patches are welded by construction and the numbering is deterministic.
class Welder {
 public:
  explicit Welder(std::size_t expected) {
    ids_.reserve(expected);
    keys_.reserve(expected);
  }
  int id(std::uint64_t key) {
    auto [it, inserted] = ids_.try_emplace(key, static_cast<int>(keys_.size()));
    if (inserted) keys_.push_back(key);
    return it->second;
  }
  const std::vector<std::uint64_t>& keys() const { return keys_; }

 private:
  std::unordered_map<std::uint64_t, int> ids_;
  std::vector<std::uint64_t> keys_;
};

Surface makePlane(const PrimitiveOptions& o) {
  const int n = o.resolution;
  Surface s;
  const auto index = [n](int i, int j) { return j * (n + 1) + i; };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      // Boundary coordinates come out exactly as +-size/2, so the area is exact.
      s.points.emplace_back(o.size * (static_cast<double>(i) / n - 0.5),
                            o.size * (static_cast<double>(j) / n - 0.5), 0.0);
      s.normals.emplace_back(0.0, 0.0, 1.0);
    }
  }
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      addQuad(s, index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    }
    report(o, 0.4 * (j + 1) / n);
  }
  return s;
}

// Geodesic sphere: each icosahedron face split into resolution^2 triangles, projected radially.
// Its triangles vary in size by less than a factor of two and have no poles.
Surface makeSphere(const PrimitiveOptions& o) {
  const double phi = std::numbers::phi;
  const std::array<Vec3d, 12> corners = {Vec3d(-1, phi, 0),  Vec3d(1, phi, 0),   Vec3d(-1, -phi, 0),
                                         Vec3d(1, -phi, 0),  Vec3d(0, -1, phi),  Vec3d(0, 1, phi),
                                         Vec3d(0, -1, -phi), Vec3d(0, 1, -phi),  Vec3d(phi, 0, -1),
                                         Vec3d(phi, 0, 1),   Vec3d(-phi, 0, -1), Vec3d(-phi, 0, 1)};
  const std::array<Triangle, 20> faces = {
      {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
       {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
       {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}}};
  const int n = o.resolution;

  // A point is identified by its integer barycentric weights on the icosahedron corners, listed
  // by corner index: every face sharing the point builds the same key, and the position is
  // computed once from it in that canonical order.
  constexpr int kWeightBits = 12;
  constexpr int kPairBits = 4 + kWeightBits;
  const auto key = [](std::array<std::pair<int, int>, 3> pairs) {
    std::sort(pairs.begin(), pairs.end());
    std::uint64_t k = 0;
    for (const auto& [corner, weight] : pairs) {
      k = (k << kPairBits) | (static_cast<std::uint64_t>(corner) << kWeightBits) |
          static_cast<std::uint64_t>(weight);
    }
    return k;
  };

  Surface s;
  Welder welder(10 * static_cast<std::size_t>(n) * n + 2);
  std::vector<int> grid((n + 1) * (n + 2) / 2);
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const auto [a, b, c] = faces[f];
    // Row j has the points i = 0..n-j; (i, j) has weights (n-i-j, i, j) on (a, b, c).
    const auto at = [n](int i, int j) { return j * (n + 1) - j * (j - 1) / 2 + i; };
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n - j; ++i) {
        // A zero weight goes in as (0, 0), which packs to zero bits: only non-zero weights count.
        const int wa = n - i - j;
        grid[at(i, j)] = welder.id(key({{{wa ? a : 0, wa}, {i ? b : 0, i}, {j ? c : 0, j}}}));
      }
    }
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n - j; ++i) {
        s.triangles.push_back({grid[at(i, j)], grid[at(i + 1, j)], grid[at(i, j + 1)]});
        if (i + j + 2 <= n) {
          s.triangles.push_back({grid[at(i + 1, j)], grid[at(i + 1, j + 1)], grid[at(i, j + 1)]});
        }
      }
    }
    report(o, 0.3 * (f + 1) / faces.size());
  }

  constexpr std::uint64_t kWeightMask = (1u << kWeightBits) - 1;
  for (std::uint64_t k : welder.keys()) {
    Vec3d q(0, 0, 0);
    for (int p = 2; p >= 0; --p) {
      const std::uint64_t pair = k >> (p * kPairBits);
      q += static_cast<double>(pair & kWeightMask) * corners[(pair >> kWeightBits) & 0xf];
    }
    const Vec3d normal = q / q.norm();
    s.normals.push_back(normal);
    s.points.push_back(o.size * normal);
  }
  report(o, 0.4);
  return s;
}

// Rounded cube = the points at distance minorRadius from the box [-a, a]^3, a = size - minorRadius.
// A subdivided cube is mapped onto it per axis by arc length: along each axis the face-centre to
// cube-edge distance is a flat part of length a followed by an eighth of a circle of radius
// minorRadius, so every grid step covers the same length of surface. The corners then become the
// equiangular cube-sphere patches, whose triangles stay well shaped.
Surface makeRoundedCube(const PrimitiveOptions& o) {
  const int n = o.resolution;
  const double r = o.minorRadius;
  const double a = o.size - r;
  const double halfLength = a + r * std::numbers::pi / 4;

  Surface s;
  Welder welder(6 * static_cast<std::size_t>(n + 1) * (n + 1));
  const auto latticeKey = [n](const std::array<int, 3>& t) {
    const auto side = static_cast<std::uint64_t>(n + 1);
    return static_cast<std::uint64_t>(t[0]) +
           side * (static_cast<std::uint64_t>(t[1]) + side * static_cast<std::uint64_t>(t[2]));
  };
  const auto place = [&](const std::array<int, 3>& t) {
    Vec3d centre, direction;
    for (int axis = 0; axis < 3; ++axis) {
      const double x = (2.0 * t[axis] / n - 1.0) * halfLength;
      centre[axis] = std::clamp(x, -a, a);
      const double angle = std::copysign(std::max(0.0, std::abs(x) - a) / r, x);
      direction[axis] = std::tan(angle);
    }
    direction /= direction.norm();
    s.points.push_back(centre + r * direction);
    s.normals.push_back(direction);
  };

  // Quad corners go counter-clockwise around e_u x e_v = e_axis, reversed on the -axis face.
  std::vector<int> grid((n + 1) * (n + 1));
  for (int face = 0; face < 6; ++face) {
    const int axis = face / 2;
    const bool positive = face % 2 == 1;
    const int u = (axis + 1) % 3;
    const int v = (axis + 2) % 3;
    for (int j = 0; j <= n; ++j) {
      for (int i = 0; i <= n; ++i) {
        std::array<int, 3> t;
        t[axis] = positive ? n : 0;
        t[u] = i;
        t[v] = j;
        const std::size_t before = welder.keys().size();
        const int id = welder.id(latticeKey(t));
        if (welder.keys().size() != before) place(t);
        grid[j * (n + 1) + i] = id;
      }
    }
    const auto g = [&](int i, int j) { return grid[j * (n + 1) + i]; };
    for (int j = 0; j < n; ++j) {
      for (int i = 0; i < n; ++i) {
        if (positive) {
          addQuad(s, g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1));
        } else {
          addQuad(s, g(i, j), g(i, j + 1), g(i + 1, j + 1), g(i + 1, j));
        }
      }
    }
    report(o, 0.4 * (face + 1) / 6);
  }
  return s;
}

Surface makeTorus(const PrimitiveOptions& o) {
  const int n = o.resolution;
  const int m = torusTubeSegments(n, o.size, o.minorRadius);
  Surface s;
  for (int i = 0; i < n; ++i) {
    const double theta = 2 * std::numbers::pi * i / n;
    for (int j = 0; j < m; ++j) {
      const double phi = 2 * std::numbers::pi * j / m;
      const Vec3d normal(std::cos(phi) * std::cos(theta), std::cos(phi) * std::sin(theta),
                         std::sin(phi));
      const Vec3d centre(o.size * std::cos(theta), o.size * std::sin(theta), 0.0);
      s.points.push_back(centre + o.minorRadius * normal);
      s.normals.push_back(normal);
    }
  }
  // d/dtheta x d/dphi is the outward normal, so (i, j) -> (i+1, j) -> (i+1, j+1) is outward.
  const auto index = [n, m](int i, int j) { return (i % n) * m + j % m; };
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < m; ++j) {
      addQuad(s, index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    }
    report(o, 0.4 * (i + 1) / n);
  }
  return s;
}

// d/dtheta x d/dz is the outward normal, so (i, j) -> (i+1, j) -> (i+1, j+1) faces outward.
Surface makeCylinder(const PrimitiveOptions& o) {
  const int n = o.resolution;
  const int rows = cylinderRows(n, o.size, o.height);
  Surface s;
  for (int j = 0; j <= rows; ++j) {
    const double z = o.height * (double(j) / rows - 0.5);
    for (int i = 0; i < n; ++i) {
      const double theta = 2 * std::numbers::pi * i / n;
      const Vec3d normal(std::cos(theta), std::sin(theta), 0.0);
      s.points.push_back(o.size * normal + Vec3d(0.0, 0.0, z));
      s.normals.push_back(normal);
    }
  }
  const auto index = [n](int i, int j) { return j * n + i % n; };
  for (int j = 0; j < rows; ++j) {
    for (int i = 0; i < n; ++i)
      addQuad(s, index(i, j), index(i + 1, j), index(i + 1, j + 1), index(i, j + 1));
    report(o, 0.4 * (j + 1) / rows);
  }
  return s;
}

std::uint64_t splitMix64(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ull;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ull;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebull;
  return x ^ (x >> 31);
}

// A value in [-1, 1] per integer lattice point, from a hash of its coordinates only.
double latticeValue(std::int64_t x, std::int64_t y, std::int64_t z) {
  const std::uint64_t h = splitMix64(
      splitMix64(splitMix64(static_cast<std::uint64_t>(x)) ^ static_cast<std::uint64_t>(y)) ^
      static_cast<std::uint64_t>(z));
  return static_cast<double>(h >> 11) * 0x1.0p-52 - 1.0;
}

// Value noise with quintic interpolation (Perlin 2002): C2, and within [-1, 1] because it is a
// convex combination of lattice values.
double valueNoise(const Vec3d& p) {
  std::array<std::int64_t, 3> cell;
  std::array<double, 3> w;
  for (int axis = 0; axis < 3; ++axis) {
    const double fl = std::floor(p[axis]);
    cell[axis] = static_cast<std::int64_t>(fl);
    const double t = p[axis] - fl;
    w[axis] = t * t * t * (t * (t * 6 - 15) + 10);
  }
  double sum = 0;
  for (int corner = 0; corner < 8; ++corner) {
    double weight = 1;
    std::array<std::int64_t, 3> c = cell;
    for (int axis = 0; axis < 3; ++axis) {
      const bool up = (corner >> axis) & 1;
      c[axis] += up;
      weight *= up ? w[axis] : 1 - w[axis];
    }
    sum += weight * latticeValue(c[0], c[1], c[2]);
  }
  return sum;
}

// Three octaves of value noise, normalised to stay within [-1, 1]. Each octave is shifted so the
// lattices of the octaves do not line up at the origin.
double reliefNoise(const Vec3d& p) {
  double sum = 0, amplitude = 1, total = 0, frequency = 1;
  for (int octave = 0; octave < 3; ++octave) {
    sum += amplitude * valueNoise(frequency * p + Vec3d(0.31, 0.57, 0.13) * (octave + 1));
    total += amplitude;
    amplitude *= 0.5;
    frequency *= 2;
  }
  return sum / total;
}

Surface makeBase(const PrimitiveOptions& o) {
  switch (o.shape) {
    case PrimitiveShape::Plane:
      return makePlane(o);
    case PrimitiveShape::Sphere:
      return makeSphere(o);
    case PrimitiveShape::RoundedCube:
      return makeRoundedCube(o);
    case PrimitiveShape::Torus:
      return makeTorus(o);
    case PrimitiveShape::Cylinder:
      return makeCylinder(o);
  }
  throw std::logic_error("unknown primitive shape");
}

// In double, so that absurd resolutions are reported instead of overflowing.
double faceCount(const PrimitiveOptions& o) {
  const double n = o.resolution;
  switch (o.shape) {
    case PrimitiveShape::Plane:
      return 2 * n * n;
    case PrimitiveShape::Sphere:
      return 20 * n * n;
    case PrimitiveShape::RoundedCube:
      return 12 * n * n;
    case PrimitiveShape::Torus:
      return 2 * n * torusTubeSegments(o.resolution, o.size, o.minorRadius);
    case PrimitiveShape::Cylinder:
      return 2 * n * cylinderRows(o.resolution, o.size, o.height);
  }
  throw std::logic_error("unknown primitive shape");
}

bool positiveFinite(double value) {
  return std::isfinite(value) && value > 0;
}

}  // namespace

std::string_view primitiveShapeName(PrimitiveShape shape) {
  switch (shape) {
    case PrimitiveShape::Plane:
      return "plane";
    case PrimitiveShape::Sphere:
      return "sphere";
    case PrimitiveShape::RoundedCube:
      return "rounded_cube";
    case PrimitiveShape::Torus:
      return "torus";
    case PrimitiveShape::Cylinder:
      return "cylinder";
  }
  throw std::logic_error("unknown primitive shape");
}

const std::vector<std::string>& primitiveShapeNames() {
  static const std::vector<std::string> names = {"plane", "sphere", "rounded_cube", "torus",
                                                 "cylinder"};
  return names;
}

PrimitiveShape parsePrimitiveShape(std::string_view name) {
  for (auto shape : {PrimitiveShape::Plane, PrimitiveShape::Sphere, PrimitiveShape::RoundedCube,
                     PrimitiveShape::Torus, PrimitiveShape::Cylinder}) {
    if (primitiveShapeName(shape) == name) return shape;
  }
  throw PrimitiveOptionError("shape", "unknown shape '" + std::string(name) +
                                          "' (plane, sphere, rounded_cube, torus or cylinder)");
}

int torusTubeSegments(int resolution, double size, double minorRadius) {
  return std::max(3, static_cast<int>(std::lround(resolution * minorRadius / size)));
}

int cylinderRows(int resolution, double size, double height) {
  const double perLength = resolution / (2 * std::numbers::pi * size);
  return std::max(1, static_cast<int>(std::lround(std::min(perLength * height, 1e9))));
}

void validatePrimitiveOptions(const PrimitiveOptions& o) {
  const std::string shape(primitiveShapeName(o.shape));
  if (!positiveFinite(o.size)) throw PrimitiveOptionError("size", "must be a number > 0");
  const bool usesMinor = o.shape == PrimitiveShape::RoundedCube || o.shape == PrimitiveShape::Torus;
  if (usesMinor && !positiveFinite(o.minorRadius)) {
    throw PrimitiveOptionError("minor_radius", "must be a number > 0");
  }
  if (o.shape == PrimitiveShape::Torus && o.minorRadius >= o.size) {
    throw PrimitiveOptionError("minor_radius", "must be below size (the major radius) for a torus");
  }
  if (o.shape == PrimitiveShape::RoundedCube && o.minorRadius > o.size) {
    throw PrimitiveOptionError("minor_radius",
                               "must be at most size (the half-extent) for a rounded cube");
  }

  if (o.shape == PrimitiveShape::Cylinder && !positiveFinite(o.height)) {
    throw PrimitiveOptionError("height", "must be a number > 0");
  }
  const bool round = o.shape == PrimitiveShape::Torus || o.shape == PrimitiveShape::Cylinder;
  const int minResolution = round ? 3 : 1;
  if (o.resolution < minResolution) {
    throw PrimitiveOptionError(
        "resolution", "must be at least " + std::to_string(minResolution) + " for a " + shape);
  }
  if (faceCount(o) > static_cast<double>(kMaxPrimitiveFaces)) {
    std::ostringstream message;
    message << "gives " << std::fixed << std::setprecision(0) << faceCount(o) << " faces for a "
            << shape << "; at most " << kMaxPrimitiveFaces << " are allowed";
    throw PrimitiveOptionError("resolution", message.str());
  }

  if (!std::isfinite(o.relief) || o.relief < 0) {
    throw PrimitiveOptionError("relief", "must be a number >= 0");
  }
  if (!positiveFinite(o.reliefFrequency)) {
    throw PrimitiveOptionError("relief_frequency", "must be a number > 0");
  }
  // Inward displacement beyond the smallest radius of curvature (or, on a torus, outward beyond
  // the hole) would fold the surface through itself.
  switch (o.shape) {
    case PrimitiveShape::Plane:
      break;
    case PrimitiveShape::Sphere:
      if (o.relief >= o.size) {
        throw PrimitiveOptionError("relief", "must be below size (the radius)");
      }
      break;
    case PrimitiveShape::RoundedCube:
      if (o.relief >= o.minorRadius) {
        throw PrimitiveOptionError("relief", "must be below minor_radius (the edge radius)");
      }
      break;
    case PrimitiveShape::Cylinder:
      if (o.relief >= o.size) {
        throw PrimitiveOptionError("relief", "must be below size (the radius)");
      }
      break;
    case PrimitiveShape::Torus:
      if (o.relief >= o.minorRadius || o.minorRadius + o.relief >= o.size) {
        throw PrimitiveOptionError("relief",
                                   "must be below minor_radius and below size - minor_radius");
      }
      break;
  }
}

std::size_t primitiveFaceCount(const PrimitiveOptions& options) {
  validatePrimitiveOptions(options);
  return static_cast<std::size_t>(faceCount(options));
}

TriMesh makePrimitive(const PrimitiveOptions& options) {
  validatePrimitiveOptions(options);
  Surface s = makeBase(options);

  TriMesh mesh;
  mesh.reserve(s.points.size(), s.points.size() + s.triangles.size(), s.triangles.size());
  const double cellsPerLength = options.reliefFrequency / options.size;
  for (std::size_t i = 0; i < s.points.size(); ++i) {
    Vec3d p = s.points[i];
    if (options.relief > 0) p += options.relief * reliefNoise(cellsPerLength * p) * s.normals[i];
    mesh.add_vertex(p);
  }
  report(options, 0.5);

  constexpr std::size_t kProgressStride = 1 << 16;
  for (std::size_t f = 0; f < s.triangles.size(); ++f) {
    const auto& t = s.triangles[f];
    const auto face = mesh.add_face(TriMesh::VertexHandle(t[0]), TriMesh::VertexHandle(t[1]),
                                    TriMesh::VertexHandle(t[2]));
    if (!face.is_valid()) throw std::logic_error("primitive: non-manifold triangle generated");
    if (f % kProgressStride == kProgressStride - 1) {
      report(options, 0.5 + 0.5 * static_cast<double>(f) / s.triangles.size());
    }
  }
  report(options, 1.0);
  return mesh;
}

}  // namespace geobrush
