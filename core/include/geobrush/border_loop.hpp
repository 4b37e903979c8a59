// A hole's border on a mesh: one boundary loop of it, its vertices in order (the border B of
// surface inpainting, Freeform surface inpainting section 4).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"

namespace geobrush {

class BorderLoop final : public Value {
 public:
  static constexpr std::string_view kTypeId = "geobrush.BorderLoop";
  std::string_view typeId() const override { return kTypeId; }
  Hash contentHash() const override;
  std::string summary() const override;

  MeshPtr mesh;             // the holed mesh
  std::vector<int> vertex;  // a boundary loop of `mesh`, in the order of its boundary halfedges
};
using BorderLoopPtr = std::shared_ptr<const BorderLoop>;

// Whether `vertex` is, in order, a closed loop of boundary halfedges of `mesh` (each vertex's
// outgoing boundary halfedge leads to the next); an empty string if so, else why not.
std::string borderLoopProblem(const TriMesh& mesh, const std::vector<int>& vertex);

// Every boundary loop of `mesh`, each starting at its lowest vertex index, the loops ordered by
// that vertex.
std::vector<std::vector<int>> boundaryLoops(const TriMesh& mesh);

}  // namespace geobrush
