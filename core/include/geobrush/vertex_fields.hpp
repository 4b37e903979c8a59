// Per-vertex scalar fields: named columns of doubles tied to the mesh they were computed on (the
// EMD detail transfer's signal g, its modes h_k and residue r_m, the transferred signal g^).
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

// A hash of a mesh's geometry and connectivity only (points and faces, not colours): what a field
// belongs to, so that colouring a mesh by its fields keeps them attached.
Hash geometryHash(const TriMesh& mesh);

class Context;
// geometryHash of a mesh that a node's input holds, as derived data (Context::derivedFrom): the
// nodes of an evaluation that check fields against one mesh value hash it once, not every edit.
Hash derivedGeometryHash(Context& ctx, const MeshPtr& mesh);

class VertexFields final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.VertexFields";

  VertexFields() = default;
  // Empty fields on `mesh`.
  explicit VertexFields(const TriMesh& mesh);
  // Empty fields on a mesh of `vertexCount` vertices whose geometryHash is `meshHash`.
  VertexFields(std::size_t vertexCount, Hash meshHash);

  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  // Appends a column; throws std::invalid_argument when its length is not vertexCount or the
  // name is empty or taken.
  void add(std::string name, std::vector<double> values);
  // The column named `name`, or nullptr.
  const std::vector<double>* find(std::string_view name) const;
  // The column named `name`; throws std::out_of_range naming it and the columns there are.
  const std::vector<double>& column(std::string_view name) const;
  // The names of the columns, in the order they were added.
  std::vector<std::string> names() const;
  // The intrinsic modes' names (emd's h1, h2, ...), from h1 on as far as they run.
  std::vector<std::string> modeNames() const;
  // Empty when the fields belong to `mesh`; else why not ("computed on a mesh of 100 vertices,
  // this one has 120", "same vertex count, other geometry").
  std::string mismatch(const TriMesh& mesh) const;
  // The same, with the mesh's geometryHash given.
  std::string mismatch(const TriMesh& mesh, Hash meshGeometry) const;

  Hash meshHash = 0;            // geometryHash of the mesh they belong to
  std::size_t vertexCount = 0;  // its vertex count: every column's length
  std::vector<std::pair<std::string, std::vector<double>>> columns;
};
using VertexFieldsPtr = std::shared_ptr<const VertexFields>;

}  // namespace geobrush
