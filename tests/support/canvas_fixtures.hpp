// Parameterized canvases with known geometry, for the preprocess suites.
#pragma once

#include <Eigen/Geometry>
#include <functional>
#include <memory>

#include "geobrush/canvas.hpp"

namespace geobrush::test {

// An n x n grid of quads over [-1, 1]^2 with heights z(x, y), mapped by `rigid`.
MeshPtr heightGrid(int n, const std::function<double(double, double)>& z,
                   const Eigen::Isometry3d& rigid = Eigen::Isometry3d::Identity());

// The height field z = height(x, y) over [-1, 1]^2 with n x n quads,
// parameterized by projection: uv = (x, y), normals +z.
std::shared_ptr<Parameterization> heightFieldParameterization(
    int n, const std::function<double(double, double)>& height);

// A canvas grown as canvas_grow does, without its checks: the faces with
// every corner within `radius` of the origin, flood-filled from `face`; the
// origin is the point of `face` with barycentric weights 0.5, 0.3, 0.2.
Canvas growDiscCanvas(const MeshPtr& mesh, int face, double radius);

// growDiscCanvas on a flat mesh in the plane z = 0, parameterized by projection: uv = (x, y),
// normals +z.
std::shared_ptr<Parameterization> flatDiscParameterization(const MeshPtr& mesh, int face,
                                                           double radius);

// ../shared/data/meshes/mountain.obj, a height field over the xz plane with
// +y up, parameterized by projection: uv = (x, -z), so (u, v, normal) is
// right-handed.
std::shared_ptr<Parameterization> terrainParameterization();

// Whether the canvas boundary, mapped to the plane by uv, is a simple polygon: no two edges that
// do not share a corner touch.
bool boundaryIsSimple(const Canvas& canvas, const std::vector<Eigen::Vector2d>& uv);

}  // namespace geobrush::test
