// The heavy headers the studio's sources share (Qt Widgets, Eigen, the mesh value and the graph),
// precompiled once for the studio library.
#pragma once

#include <QtWidgets>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/mesh.hpp"
#include "geobrush/values.hpp"
