// The heavy headers nearly every node includes, precompiled once and shared by the node
// libraries built in this tree (cmake/GeoBrushNode.cmake): Eigen, OpenMesh through the mesh
// value, and the node API.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
