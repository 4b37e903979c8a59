// The heavy headers nearly every suite includes, precompiled once and shared by the suites
// (tests/CMakeLists.txt): GoogleTest, Eigen, OpenMesh through the mesh value, the graph API.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/SparseCore>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "geobrush/canvas.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/mesh_io.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
