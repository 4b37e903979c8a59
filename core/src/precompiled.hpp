// The heavy headers most of core includes (Eigen, OpenMesh through the mesh value, the standard
// containers), precompiled once for the core library's sources.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/values.hpp"
