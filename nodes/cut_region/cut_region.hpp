// Stage 1 of surface inpainting: the damaged region removed from the mesh, leaving a hole and its
// ordered border B (Freeform surface inpainting, section 4 / Fig. 2 stage 1).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/region.hpp"

namespace geobrush {

// A refused input; `port` names the node port it concerns: "mesh", "canvas", "strokes" or the
// param "near".
class CutRegionError : public std::runtime_error {
 public:
  CutRegionError(std::string port, const std::string& message)
      : std::runtime_error(message), port_(std::move(port)) {}
  const std::string& port() const { return port_; }

 private:
  std::string port_;
};

struct CutRegionOptions {
  // Per mesh vertex, nonzero where painted: every face with a painted corner is removed. Empty:
  // nothing is removed and the border is the mesh's existing boundary loop nearest `near`.
  std::vector<char> painted;
  // Picks the existing loop: the one with the vertex nearest this point (ties: the lowest vertex).
  Eigen::Vector3d near = Eigen::Vector3d::Zero();
};

struct CutRegionResult {
  TriMesh mesh;             // the holed mesh, one manifold component
  std::vector<int> border;  // its boundary loop B, from its lowest vertex, in halfedge order
  TriMesh removed;          // the removed faces as a mesh of their own; empty when none
  // Where each element came from in the input; both meshes keep the input's relative order.
  std::vector<int> keptVertex;     // mesh vertex -> input vertex
  std::vector<int> keptFace;       // mesh face -> input face
  std::vector<int> removedVertex;  // removed vertex -> input vertex
  std::vector<int> removedFace;    // removed face -> input face
  std::size_t paintedVertices = 0;
  std::size_t paintedFaces = 0;  // faces with a painted corner
  // Unpainted faces removed too, so that the rest stays one manifold piece: islands cut off by
  // the region and the smaller wedges at vertices where the cut left several.
  std::size_t cleanedFaces = 0;
};

// The mesh vertices whose canvas vertex `strokes` paints at its uv.
struct Painting {
  std::vector<char> painted;  // per mesh vertex
  std::size_t count = 0;
  // Whether a painted vertex lies on the canvas' own boundary: the painting may reach beyond the
  // canvas, where the mesh is not painted.
  bool reachesCanvasBorder = false;
};

// Refuses (CutRegionError on "canvas") a parameterization whose canvas does not lie on `mesh`
// (its source is another mesh's content) or whose arrays disagree, and (on "strokes") a
// painting that selects no vertex.
Painting paintedVertices(const Mesh& mesh, const Parameterization& canvas, const Strokes& strokes);

// Removes the painted region (or, without a painting, picks an existing hole) and returns the
// holed mesh with its border. Refuses a mesh that is not one manifold component (port "mesh"), a
// painting that removes nothing, everything, or opens other than one new loop away from the
// mesh's existing holes ("strokes").
CutRegionResult cutRegion(const TriMesh& mesh, const CutRegionOptions& options);

}  // namespace geobrush
