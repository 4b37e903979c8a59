#include "save_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>

namespace geobrush {
namespace {

std::string quoted(const std::filesystem::path& path) {
  std::string text = "'";
  text += path.string();
  text += '\'';
  return text;
}

std::string count(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// How many coordinates a 32-bit float changes, and by how much at most.
struct Rounding {
  std::size_t changed = 0;
  double largest = 0;
};

Rounding roundToFloat(const TriMesh& mesh) {
  Rounding rounding;
  for (auto vertex : mesh.vertices()) {
    for (double x : mesh.point(vertex)) {
      const double change = std::abs(x - double(float(x)));
      if (change > 0) ++rounding.changed;
      rounding.largest = std::max(rounding.largest, change);
    }
  }
  return rounding;
}

// Vertices at the position of an earlier one, as STL's 32-bit floats see them.
std::size_t sharedPositions(const TriMesh& mesh) {
  std::vector<std::array<float, 3>> points;
  points.reserve(mesh.n_vertices());
  for (auto vertex : mesh.vertices()) {
    if (mesh.is_isolated(vertex)) continue;
    const auto& p = mesh.point(vertex);
    points.push_back({float(p[0]), float(p[1]), float(p[2])});
  }
  std::sort(points.begin(), points.end());
  return points.size() - std::size_t(std::unique(points.begin(), points.end()) - points.begin());
}

}  // namespace

SaveMeshPlan planMeshSave(const Mesh& mesh, const SaveMeshOptions& options) {
  const auto& destination = options.destination;
  if (destination.empty()) throw MeshError("no file given");
  const auto format = meshFormatFromPath(destination);
  if (!format) {
    throw MeshError(quoted(destination) + ": unknown mesh format '" +
                    destination.extension().string() + "' (supported: .obj, .ply, .off, .stl)");
  }
  std::error_code ec;
  const auto folder =
      destination.parent_path().empty() ? std::filesystem::path(".") : destination.parent_path();
  if (!std::filesystem::is_directory(folder, ec)) {
    throw MeshError(quoted(destination) + ": the folder " + quoted(folder) + " does not exist");
  }
  if (std::filesystem::is_directory(destination, ec))
    throw MeshError(quoted(destination) + ": is a folder");
  if (const auto reason = unwritableReason(mesh.surface, *format))
    throw MeshError(quoted(destination) + ": " + *reason);

  SaveMeshPlan plan;
  plan.format = *format;
  const std::string name = quoted(destination) + ": ";
  const std::string formatName(toString(*format));
  if (!mesh.vertexColors.empty())
    plan.warnings.push_back(name + "vertex colours are not saved (only points and faces are)");
  if (*format != MeshFormat::Obj) {
    const Rounding rounding = roundToFloat(mesh.surface);
    if (rounding.changed > 0) {
      char largest[32];
      std::snprintf(largest, sizeof largest, "%.3g", rounding.largest);
      plan.warnings.push_back(name + formatName + " holds 32-bit floats: " +
                              count(rounding.changed, "coordinate", "coordinates") +
                              " rounded, by up to " + largest + " (OBJ keeps them exact)");
    }
  }
  if (*format == MeshFormat::Stl) {
    std::size_t isolated = 0;
    for (auto vertex : mesh.surface.vertices())
      isolated += mesh.surface.is_isolated(vertex);
    if (isolated > 0) {
      plan.warnings.push_back(name + "STL holds triangles only: " +
                              count(isolated, "vertex of no face is", "vertices of no face are") +
                              " not saved");
    }
    if (const std::size_t shared = sharedPositions(mesh.surface); shared > 0) {
      plan.warnings.push_back(name + "STL holds triangle corners only: " +
                              count(shared, "vertex shares its", "vertices share their") +
                              " position with another and will be merged with it on reading");
    }
  }
  return plan;
}

}  // namespace geobrush
