// The discrete exponential map of a canvas (shared by the source and target parameterizations),
// original (Schmidt, Grimm, Wyvill 2006: SGW06) and generalized (GeoBrush paper section 4.2), with
// the reversed-face flags of section 4.5.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"

namespace geobrush {

struct DemOptions {
  // true: the generalized map of section 4.2 (Eq. 1 normals, k-nearest-neighbour propagation,
  // no rescaling). false: the original DEM of SGW06 (surface normals, mesh-edge neighbours,
  // steps rescaled to their 3D length).
  bool generalized = true;
  // Turns the (u, v) axes about the origin normal by this many degrees, counter-clockwise seen
  // from the normal's tip. At 0 the v axis is the global +y projected onto the origin's tangent
  // plane (+z when the normal is parallel to y). Turning the axes by a turns the map by -a.
  double angleDegrees = 0;
  // k of the k-nearest-neighbour graph (generalized only).
  int neighbours = 8;
  // Eq. 1's epsilon, relative to the squared bounding-box diagonal of the canvas.
  double epsilon = 1e-3;
  // A face is reversed when its unit normal . the (normalized, averaged) DEM normal of its
  // corners is below this (section 4.5: 0, or a small positive number to catch steep flanks).
  double reversedThreshold = 0;
  // Reversed flags grow by this many vertex rings (section 4.5 uses 3).
  int reversedRing = 3;
  // Threads for the per-vertex steps; 0: one per hardware thread. The result is the same for any
  // count.
  int threads = 0;
};

// An input that gives no map. `option()` names the field to change: "canvas", "angle",
// "neighbours", "epsilon", "reversed_threshold", "reversed_ring" or "threads".
class DemError : public std::invalid_argument {
 public:
  DemError(std::string option, const std::string& message)
      : std::invalid_argument(message), option_(std::move(option)) {}
  const std::string& option() const { return option_; }

 private:
  std::string option_;
};

struct DemResult {
  std::vector<Eigen::Vector2d> uv;      // per canvas surface vertex
  std::vector<Eigen::Vector3d> normal;  // per canvas surface vertex: the normals projected along
  Frame origin;                         // at the canvas origin point, uv (0, 0)
  std::vector<std::uint8_t> reversedFaces;  // per canvas face, after ring growth
};

// The angle-weighted sum of the face normals around `v` (not normalized; zero where the faces are
// degenerate or cancel out).
Eigen::Vector3d angleWeightedNormal(const TriMesh& mesh, TriMesh::VertexHandle v);

// Angle-weighted vertex normals of the source mesh at each canvas vertex, so that boundary
// vertices see their whole one-ring (the canvas surface itself when it has no source). Throws
// DemError("canvas") for a vertex whose faces' normals cancel out. `threads` as in DemOptions.
std::vector<Eigen::Vector3d> surfaceNormals(const Canvas& canvas, int threads = 0);

// Eq. 1: boundary vertices keep `surface`; every other vertex gets the normalized sum of the
// boundary normals weighted by 1 / (|w - v|^2 + epsilon * diagonal^2), so `surface` is read only
// on the boundary. Throws DemError("canvas") where the boundary normals cancel out (a canvas
// wrapped around far more than a hemisphere). The sums are exact up to the order of additions.
std::vector<Eigen::Vector3d> interpolatedNormals(const Canvas& canvas,
                                                 const std::vector<Eigen::Vector3d>& surface,
                                                 double epsilon, int threads = 0);

// The frame at the origin point: the normal interpolated over the origin face from `normals`,
// the axes as described for DemOptions::angleDegrees.
Frame originFrame(const Canvas& canvas, const std::vector<Eigen::Vector3d>& normals,
                  double angleDegrees);

// The same for a point of the triangle `corners` with per-corner `normals`.
Frame originFrame(const std::array<Eigen::Vector3d, 3>& corners,
                  const std::array<Eigen::Vector3d, 3>& normals, const Eigen::Vector3d& point,
                  double angleDegrees);

// For every point, its k nearest other points (all others when there are fewer), sorted by
// distance, ties by index. Exact; a uniform grid keeps it near O(n k log k).
std::vector<std::vector<int>> nearestNeighbours(const std::vector<Eigen::Vector3d>& points, int k,
                                                int threads = 0);

// The DEM propagation (SGW06): vertices are fixed in order of increasing Dijkstra distance from
// the origin point over `adjacency` (3D edge lengths, ties by index). A new vertex p gets the
// average, weighted by 1 / |p - q|, over its fixed neighbours q of uv(q) + the components of
// p - q along q's frame axes (the projection onto q's tangent plane), that projection rescaled to
// |p - q| when `rescale`. q's frame is its Dijkstra parent's frame rotated by the smallest
// rotation taking the parent's normal to normal(q) (discrete parallel transport). The origin
// face's corners count the origin point as a neighbour. `adjacency` must be symmetric.
std::vector<Eigen::Vector2d> propagate(const Canvas& canvas,
                                       const std::vector<Eigen::Vector3d>& normals,
                                       const Frame& origin,
                                       const std::vector<std::vector<int>>& adjacency,
                                       bool rescale);

// The propagation of `propagate` as a resumable process over a graph given by callbacks, so that
// a region and its map can grow together (section 4.2, the target canvas). Vertices are ids in
// [0, vertexCount); state is kept only for the vertices reached, so one growth costs about the
// size of the region, not of the graph.
class ExponentialMapGrowth {
 public:
  struct Graph {
    std::size_t vertexCount = 0;
    std::function<Eigen::Vector3d(int)> point;
    // The unit normal, asked once per vertex, when it is fixed.
    std::function<Eigen::Vector3d(int)> normal;
    // Appends the neighbours of a vertex; must be symmetric.
    std::function<void(int, std::vector<int>&)> neighbours;
  };

  // `originCorners` count the origin point as a neighbour. `tiny` keeps the weights 1 / |p - q|
  // finite for coincident points.
  ExponentialMapGrowth(Graph graph, const Frame& origin, const std::vector<int>& originCorners,
                       bool rescale, double tiny);

  // Fixes the next vertex in order of Dijkstra distance (ties by id) and returns it; -1 when no
  // reachable vertex is left.
  int fixNext();

  bool isFixed(int vertex) const;
  // Of a fixed vertex.
  const Eigen::Vector2d& uv(int vertex) const;
  const Eigen::Vector3d& normal(int vertex) const;
  // The vertices fixed so far, in order.
  const std::vector<int>& order() const { return order_; }

 private:
  int slotOf(int vertex);

  // The reached, unfixed slots: a binary heap, nearest (distance, then vertex id) first, that
  // knows each slot's place in it, so that a shorter distance moves a slot up instead of queueing
  // it again.
  struct SlotQueue {
    std::vector<int> heap;
    std::vector<int> place;  // slot -> index into heap, or -1
    // Queues the slot, or moves it up after its distance dropped.
    void moveUp(int slot, const std::vector<double>& distance, const std::vector<int>& vertex);
    int popNearest(const std::vector<double>& distance, const std::vector<int>& vertex);
  };

  Graph graph_;
  Frame origin_;
  bool rescale_;
  double tiny_;
  std::vector<int> slot_;  // vertex -> index into the per-reached-vertex arrays, or -1
  std::vector<int> vertex_;
  std::vector<double> distance_;
  std::vector<int> parent_;  // -1: the origin point
  std::vector<char> fixed_, originCorner_;
  std::vector<Eigen::Vector3d> point_;
  std::vector<Frame> frame_;
  std::vector<Eigen::Vector2d> uv_;
  std::vector<int> order_;
  std::vector<int> scratch_;
  SlotQueue queue_;
};

// Section 4.5: 1 where a face's unit normal . the normalized mean of its corners' `normals` is
// below `threshold` (faces of zero area count as 0).
std::vector<std::uint8_t> reversedFaces(const TriMesh& mesh,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        double threshold);

// Flags grown `rings` times by every face sharing a vertex with a flagged face.
std::vector<std::uint8_t> growFaceRing(const TriMesh& mesh, std::vector<std::uint8_t> flags,
                                       int rings);

// The whole map: normals (Eq. 1 from the boundary's surface normals, or the surface normals),
// adjacency (symmetric k-nearest neighbours plus mesh edges, or mesh edges), propagation and
// reversed flags. Throws DemError.
DemResult discreteExponentialMap(const Canvas& canvas, const DemOptions& options);

}  // namespace geobrush
