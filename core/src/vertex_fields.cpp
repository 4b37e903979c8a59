#include "geobrush/vertex_fields.hpp"

#include <stdexcept>

#include "geobrush/node.hpp"
#include "mesh_hash.hpp"

namespace geobrush {

Hash geometryHash(const TriMesh& mesh) {
  Hasher hasher;
  hashGeometry(hasher.str("geometry"), mesh);
  return hasher.digest();
}

Hash derivedGeometryHash(Context& ctx, const MeshPtr& mesh) {
  return *ctx.derivedFrom("geometry_hash", {mesh}, 0, [&] {
    return std::make_shared<const Hash>(geometryHash(mesh->surface));
  });
}

VertexFields::VertexFields(const TriMesh& mesh)
    : meshHash(geometryHash(mesh)), vertexCount(mesh.n_vertices()) {}

VertexFields::VertexFields(std::size_t count, Hash hash) : meshHash(hash), vertexCount(count) {}

Hash VertexFields::contentHash() const {
  Hasher hasher;
  hasher.str(kTypeId).u64(meshHash).u64(vertexCount).u64(columns.size());
  for (const auto& [name, values] : columns)
    hasher.str(name).span(std::span<const double>(values));
  return hasher.digest();
}

std::string VertexFields::summary() const {
  std::string text =
      std::to_string(columns.size()) + " fields on " + std::to_string(vertexCount) + " vertices";
  for (std::size_t k = 0; k < columns.size(); ++k)
    text += (k == 0 ? ": " : ", ") + columns[k].first;
  return text;
}

void VertexFields::add(std::string name, std::vector<double> values) {
  if (name.empty()) throw std::invalid_argument("a field needs a name");
  if (find(name)) throw std::invalid_argument("a field named '" + name + "' is already there");
  if (values.size() != vertexCount)
    throw std::invalid_argument("field '" + name + "' has " + std::to_string(values.size()) +
                                " values for " + std::to_string(vertexCount) + " vertices");
  columns.emplace_back(std::move(name), std::move(values));
}

const std::vector<double>* VertexFields::find(std::string_view name) const {
  for (const auto& [columnName, values] : columns)
    if (columnName == name) return &values;
  return nullptr;
}

const std::vector<double>& VertexFields::column(std::string_view name) const {
  if (const auto* values = find(name)) return *values;
  std::string there;
  for (const auto& [columnName, values] : columns)
    there += (there.empty() ? "" : ", ") + columnName;
  throw std::out_of_range("no field named '" + std::string(name) +
                          "' (there are: " + (there.empty() ? std::string("none") : there) + ")");
}

std::vector<std::string> VertexFields::names() const {
  std::vector<std::string> result;
  for (const auto& column : columns)
    result.push_back(column.first);
  return result;
}

std::vector<std::string> VertexFields::modeNames() const {
  std::vector<std::string> result;
  for (std::string name = "h1"; find(name);
       name = std::string("h").append(std::to_string(result.size() + 1)))
    result.push_back(name);
  return result;
}

std::string VertexFields::mismatch(const TriMesh& mesh) const {
  return mismatch(mesh, mesh.n_vertices() == vertexCount ? geometryHash(mesh) : 0);
}

std::string VertexFields::mismatch(const TriMesh& mesh, Hash meshGeometry) const {
  if (mesh.n_vertices() != vertexCount)
    return "the fields were computed on a mesh of " + std::to_string(vertexCount) +
           " vertices, this one has " + std::to_string(mesh.n_vertices());
  if (meshGeometry != meshHash)
    return "the fields were computed on another mesh with the same vertex count";
  return {};
}

}  // namespace geobrush
