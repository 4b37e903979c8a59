// The discrete exponential map of a canvas, original (Schmidt, Grimm, Wyvill 2006: SGW06) and
// generalized (GeoBrush paper section 4.2), with the reversed-face flags of section 4.5.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <cstdint>
#include <stdexcept>
#include <string>
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
};

// An input that gives no map. `option()` names the field to change: "canvas", "angle",
// "neighbours", "epsilon", "reversed_threshold" or "reversed_ring".
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

// Angle-weighted vertex normals of the source mesh at each canvas vertex, so that boundary
// vertices see their whole one-ring (the canvas surface itself when it has no source). Throws
// DemError("canvas") for a vertex whose faces' normals cancel out.
std::vector<Eigen::Vector3d> surfaceNormals(const Canvas& canvas);

// Eq. 1: boundary vertices keep `surface`; every other vertex gets the normalized sum of the
// boundary normals weighted by 1 / (|w - v|^2 + epsilon * diagonal^2). Throws DemError("canvas")
// where the boundary normals cancel out (a canvas wrapped around far more than a hemisphere).
std::vector<Eigen::Vector3d> interpolatedNormals(const Canvas& canvas,
                                                 const std::vector<Eigen::Vector3d>& surface,
                                                 double epsilon);

// The frame at the origin point: the normal interpolated over the origin face from `normals`,
// the axes as described for DemOptions::angleDegrees.
Frame originFrame(const Canvas& canvas, const std::vector<Eigen::Vector3d>& normals,
                  double angleDegrees);

// For every point, its k nearest other points (all others when there are fewer), sorted by
// distance, ties by index. Exact; a uniform hash grid keeps it near O(n k log k).
std::vector<std::vector<int>> nearestNeighbours(const std::vector<Eigen::Vector3d>& points, int k);

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

// Section 4.5: 1 where a face's unit normal . the normalized mean of its corners' `normals` is
// below `threshold` (faces of zero area count as 0).
std::vector<std::uint8_t> reversedFaces(const TriMesh& mesh,
                                        const std::vector<Eigen::Vector3d>& normals,
                                        double threshold);

// Flags grown `rings` times by every face sharing a vertex with a flagged face.
std::vector<std::uint8_t> growFaceRing(const TriMesh& mesh, std::vector<std::uint8_t> flags,
                                       int rings);

// The whole map: normals (Eq. 1 or surface), adjacency (symmetric k-nearest neighbours plus mesh
// edges, or mesh edges), propagation and reversed flags. Throws DemError.
DemResult discreteExponentialMap(const Canvas& canvas, const DemOptions& options);

}  // namespace geobrush
