#include "geobrush/face_selection.hpp"

#include <algorithm>

namespace geobrush {

bool pinched(const TriMesh& mesh, TriMesh::VertexHandle v, const std::vector<char>& selected) {
  int fans = 0;
  bool previous = false, first = false, any = false;
  for (auto h : mesh.voh_range(v)) {
    const auto f = mesh.face_handle(h);
    const bool in = f.is_valid() && selected[std::size_t(f.idx())];
    if (!any) first = in;
    fans += in && any && !previous;
    previous = in;
    any = true;
  }
  // The circulation is a cycle: a fan that starts the round was not counted, unless it wraps.
  fans += first && !previous;
  return fans > 1;
}

void removePinches(const TriMesh& mesh, std::vector<char>& selected,
                   const std::vector<int>& candidateFaces) {
  std::vector<char> queued(mesh.n_vertices(), 0);
  int lowest = int(mesh.n_vertices()), highest = -1;
  auto queue = [&](TriMesh::VertexHandle v) {
    queued[std::size_t(v.idx())] = 1;
    lowest = std::min(lowest, v.idx());
    highest = std::max(highest, v.idx());
  };
  for (int f : candidateFaces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      queue(v);
  std::vector<int> candidates;
  while (highest >= 0) {
    candidates.clear();
    for (int v = lowest; v <= highest; ++v)
      if (queued[std::size_t(v)]) {
        queued[std::size_t(v)] = 0;
        candidates.push_back(v);
      }
    lowest = int(mesh.n_vertices());
    highest = -1;
    for (int v : candidates) {
      const auto vh = TriMesh::VertexHandle(v);
      if (!pinched(mesh, vh, selected)) continue;
      for (auto f : mesh.vf_range(vh))
        if (selected[std::size_t(f.idx())]) {
          selected[std::size_t(f.idx())] = 0;
          for (auto w : mesh.fv_range(f))
            queue(w);
        }
    }
  }
}

std::vector<int> selectedFaces(const std::vector<char>& selected) {
  std::vector<int> faces;
  for (std::size_t f = 0; f < selected.size(); ++f)
    if (selected[f]) faces.push_back(int(f));
  return faces;
}

std::vector<int> connectedFaces(const TriMesh& mesh, int start, const std::vector<char>& selected) {
  std::vector<char> reached(mesh.n_faces(), 0);
  std::vector<int> queue{start};
  reached[std::size_t(start)] = 1;
  for (std::size_t next = 0; next < queue.size(); ++next)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(queue[next]))) {
      const auto g = mesh.face_handle(mesh.opposite_halfedge_handle(h));
      if (!g.is_valid() || reached[std::size_t(g.idx())] || !selected[std::size_t(g.idx())])
        continue;
      reached[std::size_t(g.idx())] = 1;
      queue.push_back(g.idx());
    }
  return selectedFaces(reached);
}

void fillEnclosed(const TriMesh& mesh, std::vector<char>& selected, int outside) {
  // Breadth first through unselected faces from every unselected face on a mesh boundary.
  std::vector<char> open(mesh.n_faces(), 0);
  std::vector<int> queue;
  auto reach = [&](TriMesh::FaceHandle f) {
    if (!f.is_valid() || selected[std::size_t(f.idx())] || open[std::size_t(f.idx())]) return;
    open[std::size_t(f.idx())] = 1;
    queue.push_back(f.idx());
  };
  for (auto f : mesh.faces())
    if (mesh.is_boundary(f)) reach(f);
  if (outside >= 0) reach(TriMesh::FaceHandle(outside));
  for (std::size_t next = 0; next < queue.size(); ++next)
    for (auto h : mesh.fh_range(TriMesh::FaceHandle(queue[next])))
      reach(mesh.face_handle(mesh.opposite_halfedge_handle(h)));
  for (std::size_t f = 0; f < selected.size(); ++f)
    if (!open[f]) selected[f] = 1;
}

}  // namespace geobrush
