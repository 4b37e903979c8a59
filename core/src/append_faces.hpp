// appendFaces with the memory of an earlier call's maps.
#pragma once

#include <vector>

#include "geobrush/submesh.hpp"

namespace geobrush {

// appendFaces, its index maps built in the arrays of `storage` (an earlier call's account of
// faces of a mesh of the same size, whose content is dropped): on a large mesh the maps are
// megabytes, and memory already in use spares their allocation and first touch.
AppendedFaces appendFacesReusing(TriMesh& out, const TriMesh& mesh, const std::vector<int>& faces,
                                 AppendedFaces storage);

}  // namespace geobrush
