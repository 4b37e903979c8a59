// Procedural surfaces (plane, sphere, rounded cube, torus, open cylinder) with optional relief
// detail, so
// that graphs, tests and templates have well-shaped meshes with known geometry and no input
// files.
#pragma once

#include <cstddef>
#include <functional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

enum class PrimitiveShape { Plane, Sphere, RoundedCube, Torus, Cylinder };

// The shape names used in graph files: "plane", "sphere", "rounded_cube", "torus", "cylinder".
std::string_view primitiveShapeName(PrimitiveShape shape);
const std::vector<std::string>& primitiveShapeNames();
// Throws PrimitiveOptionError("shape", ...) for an unknown name.
PrimitiveShape parsePrimitiveShape(std::string_view name);

struct PrimitiveOptions {
  PrimitiveShape shape = PrimitiveShape::Sphere;
  // Plane side length, sphere radius, cube half-extent, torus major radius or cylinder radius.
  double size = 1.0;
  // Torus tube radius or rounded-cube edge radius; unused by the plane and the sphere.
  double minorRadius = 0.25;
  // Cylinder height along z; unused by the other shapes.
  double height = 2.0;
  // Plane: quads per side. Sphere: segments per icosahedron edge. Rounded cube: quads per
  // cube-face side. Torus: segments around the major circle (the tube gets as many per length).
  // Cylinder: segments around (the height gets as many per length).
  int resolution = 64;
  // Largest displacement along the smooth normal; 0 gives the exact shape.
  double relief = 0.0;
  // Relief noise cells per `size` length.
  double reliefFrequency = 4.0;
  // Called with the fraction done; may throw to abandon the build.
  std::function<void(double)> progress;
};

// Meshes above this many faces are refused: a 5M-vertex sculpt, the largest target the live
// brush is measured on, has 10M.
inline constexpr std::size_t kMaxPrimitiveFaces = 10'000'000;

// An option out of its valid range. `option()` is the option's graph-file name
// ("size", "minor_radius", "height", "resolution", "relief", "relief_frequency", "shape").
class PrimitiveOptionError : public std::invalid_argument {
 public:
  PrimitiveOptionError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

// Tube segments of a torus: as many per length as around the major circle, at least 3.
int torusTubeSegments(int resolution, double size, double minorRadius);

// Rows of quads along a cylinder's height: as many per length as around it, at least 1.
int cylinderRows(int resolution, double size, double height);

// Number of triangles makePrimitive gives for these options (relief does not change it).
std::size_t primitiveFaceCount(const PrimitiveOptions& options);

// Throws PrimitiveOptionError when the options cannot give a valid surface: non-positive or
// non-finite sizes, a torus tube not thinner than its major radius, an edge radius above the
// half-extent, relief deep enough to fold the surface, or more than kMaxPrimitiveFaces faces.
void validatePrimitiveOptions(const PrimitiveOptions& options);

// A deterministic triangle mesh of the shape, centred at the origin. The sphere, rounded cube
// and torus (around the z axis) are closed, manifold, welded and oriented outward; the plane is
// the square [-size/2, size/2]^2 at z = 0 facing +z with one boundary loop; the cylinder is the
// open tube of radius `size` around the z axis, z in [-height/2, height/2], facing outward, with
// two boundary loops. Relief displaces each
// vertex along the exact normal of the base shape by `relief` times a fractal value noise in
// [-1, 1] of its base position. Throws PrimitiveOptionError (see validatePrimitiveOptions).
TriMesh makePrimitive(const PrimitiveOptions& options);

}  // namespace geobrush
