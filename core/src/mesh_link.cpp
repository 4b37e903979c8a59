// A file's polygons as one OpenMesh triangle mesh, linked in time linear in the file's size.
//
// OpenMesh's add_face, called face by face, walks around a vertex at every face added there, so a
// file whose many faces meet at one vertex in scattered order takes quadratic time (a 1 MB fan
// took seconds). Here the whole halfedge structure is set at once, as add_face would leave it
// where every vertex has one fan of faces: edges numbered in the order the faces first use them,
// halfedge 2e running the way its first face runs it, a face's halfedge the one into its first
// corner, a boundary vertex's halfedge its outgoing boundary halfedge and an inner vertex's the
// one in the last face around it. Faces that cannot join the others are split off onto copies of
// their corners (OpenMesh's fixed_nonmanifold status), as OpenMesh's importer does:
//   - a face that would run an edge the way an earlier face already runs it (a third face on an
//     edge, or two faces oriented against each other), decided in file order;
//   - at a vertex whose faces form a closed fan and more, the faces of the fans other than the
//     one of the vertex's first face where that fan is closed, else the closed fans.
// Several open fans at a vertex (a bow tie) stay joined there, as add_face joins them.
#include <algorithm>
#include <array>
#include <unordered_map>

#include "mesh_read.hpp"

namespace geobrush::meshread {
namespace {

using HalfedgeHandle = TriMesh::HalfedgeHandle;

struct Triangles {
  std::vector<std::array<int, 3>> corners;
  std::vector<std::size_t> polygon;  // the file's polygon each triangle comes from
};

// Fan-triangulates the usable polygons, counting the others.
Triangles triangulate(const PolygonSoup& soup, ImportCounts& counts) {
  Triangles triangles;
  triangles.corners.reserve(soup.ends.size());
  triangles.polygon.reserve(soup.ends.size());
  const int points = static_cast<int>(soup.points.size());
  std::vector<int> sorted;
  std::size_t begin = 0;
  for (std::size_t p = 0; p < soup.ends.size(); begin = soup.ends[p++]) {
    const std::size_t size = soup.ends[p] - begin;
    const int* corner = soup.corners.data() + begin;
    ++counts.offered;
    if (size < 3) {
      ++counts.tooFewCorners;
      continue;
    }
    if (std::any_of(corner, corner + size, [&](int v) { return v < 0 || v >= points; })) {
      ++counts.badIndex;
      continue;
    }
    sorted.assign(corner, corner + size);
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) {
      ++counts.repeatedVertex;
      continue;
    }
    if (size > 3) {
      ++counts.triangulated;
      counts.triangles += size - 2;
    }
    for (std::size_t i = 1; i + 1 < size; ++i) {
      triangles.corners.push_back({corner[0], corner[i], corner[i + 1]});
      triangles.polygon.push_back(p);
    }
  }
  return triangles;
}

std::uint64_t key(int from, int to) {
  return std::uint64_t(std::uint32_t(from)) << 32 | std::uint32_t(to);
}

// The triangles around each vertex, and which of them are kept joined.
class Fans {
 public:
  explicit Fans(const Triangles& triangles, std::size_t points)
      : triangles_(triangles), joined_(triangles.corners.size(), 1) {
    faceOf_.reserve(3 * triangles.corners.size());
    joinEdgesInOrder();
    listCornersOfVertices(points);
  }

  bool joined(std::size_t t) const { return joined_[t]; }

  // The joined triangle that runs from -> to, or -1.
  int faceRunning(int from, int to) const {
    const auto it = faceOf_.find(key(from, to));
    return it != faceOf_.end() && joined_[std::size_t(it->second)] ? it->second : -1;
  }

  // The corners (3t + i) of vertex v in joined triangles, in triangle order.
  std::vector<int> cornersOf(int v) const {
    std::vector<int> corners;
    for (int c = firstCorner_[std::size_t(v)]; c < firstCorner_[std::size_t(v) + 1]; ++c)
      if (joined_[std::size_t(vertexCorner_[std::size_t(c)] / 3)])
        corners.push_back(vertexCorner_[std::size_t(c)]);
    return corners;
  }

  int vertexAt(int corner) const { return triangles_.corners[std::size_t(corner / 3)][corner % 3]; }
  int nextAt(int corner) const { return corner - corner % 3 + (corner % 3 + 1) % 3; }
  int previousAt(int corner) const { return corner - corner % 3 + (corner % 3 + 2) % 3; }

  // The corner of v in the joined triangle across v's outgoing edge in corner's triangle (the next
  // around v), or -1 at a boundary.
  int successor(int corner) const {
    const int v = vertexAt(corner), x = vertexAt(nextAt(corner));
    const int t = faceRunning(x, v);
    return t < 0 ? -1 : cornerOf(t, v);
  }
  int predecessor(int corner) const {
    const int v = vertexAt(corner), y = vertexAt(previousAt(corner));
    const int t = faceRunning(v, y);
    return t < 0 ? -1 : cornerOf(t, v);
  }

  void splitOff(std::size_t t) { joined_[t] = 0; }

 private:
  int cornerOf(int t, int v) const {
    const auto& c = triangles_.corners[std::size_t(t)];
    return 3 * t + (c[0] == v ? 0 : c[1] == v ? 1 : 2);
  }

  // A triangle joins when none of its edges is run its way by a triangle before it.
  void joinEdgesInOrder() {
    for (std::size_t t = 0; t < triangles_.corners.size(); ++t) {
      const auto& c = triangles_.corners[t];
      bool free = true;
      for (int i = 0; i < 3 && free; ++i)
        free = !faceOf_.contains(key(c[std::size_t(i)], c[std::size_t((i + 1) % 3)]));
      if (!free) {
        joined_[t] = 0;
        continue;
      }
      for (int i = 0; i < 3; ++i)
        faceOf_.emplace(key(c[std::size_t(i)], c[std::size_t((i + 1) % 3)]), int(t));
    }
  }

  void listCornersOfVertices(std::size_t points) {
    firstCorner_.assign(points + 1, 0);
    for (const auto& c : triangles_.corners)
      for (int v : c)
        ++firstCorner_[std::size_t(v) + 1];
    for (std::size_t v = 0; v < points; ++v)
      firstCorner_[v + 1] += firstCorner_[v];
    vertexCorner_.resize(3 * triangles_.corners.size());
    std::vector<int> filled(firstCorner_.begin(), firstCorner_.end() - 1);
    for (std::size_t t = 0; t < triangles_.corners.size(); ++t)
      for (int i = 0; i < 3; ++i)
        vertexCorner_[std::size_t(filled[std::size_t(triangles_.corners[t][std::size_t(i)])]++)] =
            int(3 * t) + i;
  }

  const Triangles& triangles_;
  std::vector<char> joined_;
  std::unordered_map<std::uint64_t, int> faceOf_;  // (from, to) -> the triangle running it
  std::vector<int> firstCorner_;                   // vertex v's corners: [first[v], first[v + 1])
  std::vector<int> vertexCorner_;
};

// The fans of joined triangles around one vertex: open fans from the corner with no predecessor
// to the one with no successor, closed fans as cycles.
struct Fan {
  std::vector<int> corners;  // in order around the vertex
  bool closed = false;
};

// `seen` holds a zero for every corner of the mesh and is left so.
std::vector<Fan> fansAround(const Fans& fans, int v, std::vector<char>& seen) {
  const std::vector<int> corners = fans.cornersOf(v);
  std::vector<Fan> result;
  const auto walk = [&](int start, bool closed) {
    Fan fan{{}, closed};
    for (int c = start; c >= 0 && !seen[std::size_t(c)]; c = fans.successor(c)) {
      seen[std::size_t(c)] = 1;
      fan.corners.push_back(c);
    }
    result.push_back(std::move(fan));
  };
  for (int c : corners)
    if (fans.predecessor(c) < 0) walk(c, false);
  for (int c : corners)
    if (!seen[std::size_t(c)]) walk(c, true);
  for (int c : corners)
    seen[std::size_t(c)] = 0;
  return result;
}

// OpenMesh can join a vertex's open fans, but not a closed fan with anything else.
void splitClosedFansOff(Fans& fans, std::size_t points, std::vector<char>& seen) {
  for (int v = 0; v < int(points); ++v) {
    std::vector<Fan> around = fansAround(fans, v, seen);
    if (around.size() < 2 ||
        std::none_of(around.begin(), around.end(), [](const Fan& f) { return f.closed; }))
      continue;
    const auto firstCorner = [](const Fan& f) {
      return *std::min_element(f.corners.begin(), f.corners.end());
    };
    const auto kept = std::min_element(
        around.begin(), around.end(),
        [&](const auto& a, const auto& b) { return firstCorner(a) < firstCorner(b); });
    for (auto fan = around.begin(); fan != around.end(); ++fan) {
      if (fan == kept || (!kept->closed && !fan->closed)) continue;
      for (int c : fan->corners)
        fans.splitOff(std::size_t(c / 3));
    }
  }
}

// The mesh's faces: every joined or split-off triangle in order, split-off ones on copies of their
// corners, numbered after the file's vertices in order.
struct Layout {
  std::vector<std::array<int, 3>> faces;
  std::vector<int> copyOf;      // vertex (file vertices + i) copies file vertex copyOf[i]
  std::vector<int> copyCorner;  // and is the corner 3k + j of face k
  std::vector<char> split;      // per face
};

Layout layOut(const Triangles& triangles, const Fans& fans, std::size_t points,
              ImportCounts& counts) {
  Layout layout;
  layout.faces.reserve(triangles.corners.size());
  layout.split.reserve(triangles.corners.size());
  for (std::size_t t = 0; t < triangles.corners.size(); ++t) {
    std::array<int, 3> face = triangles.corners[t];
    const bool split = !fans.joined(t);
    if (split) {
      if (counts.nonManifold++ == 0) counts.firstNonManifold = triangles.polygon[t];
      for (int j = 0; j < 3; ++j) {
        layout.copyOf.push_back(face[std::size_t(j)]);
        layout.copyCorner.push_back(int(3 * t) + j);
        face[std::size_t(j)] = int(points + layout.copyOf.size() - 1);
      }
    }
    layout.faces.push_back(face);
    layout.split.push_back(split);
  }
  return layout;
}

// Halfedge 2e + s is side s of edge e, as in OpenMesh.
struct Halfedges {
  std::vector<int> faceHalfedge;  // face k's halfedge out of corner i: 3k + i
  std::vector<int> to;            // per halfedge
  std::vector<int> face;          // per halfedge, -1 on the boundary
  std::size_t edges() const { return to.size() / 2; }
};

// Edges in the order the faces first use them, halfedge 2e running the way its first face runs it.
Halfedges numberEdges(const Layout& layout) {
  Halfedges halfedges;
  halfedges.faceHalfedge.resize(3 * layout.faces.size());
  std::unordered_map<std::uint64_t, int> edgeOf;  // (min, max) vertex -> edge
  edgeOf.reserve(3 * layout.faces.size() / 2);
  for (std::size_t k = 0; k < layout.faces.size(); ++k) {
    const auto& f = layout.faces[k];
    for (std::size_t i = 0; i < 3; ++i) {
      const int from = f[i], to = f[(i + 1) % 3];
      const auto [it, added] =
          edgeOf.try_emplace(key(std::min(from, to), std::max(from, to)), int(halfedges.edges()));
      if (added) {
        halfedges.to.insert(halfedges.to.end(), {to, from});
        halfedges.face.insert(halfedges.face.end(), {-1, -1});
      }
      const int h = 2 * it->second + (halfedges.to[std::size_t(2 * it->second)] != to);
      halfedges.faceHalfedge[3 * k + i] = h;
      halfedges.face[std::size_t(h)] = int(k);
    }
  }
  return halfedges;
}

// Per vertex, its halfedge and the boundary's next links through it. The boundary runs in along
// each open fan's last edge and out along the next fan's first edge, so that circulating around
// the vertex passes every fan, as add_face links several fans.
void linkVertices(TriMesh& out, const Layout& layout, const Halfedges& halfedges, const Fans& fans,
                  std::size_t points) {
  std::vector<char> seen(3 * layout.faces.size(), 0);
  std::vector<std::pair<int, int>> boundary;  // (in, out) of each open fan
  const auto link = [&](int v, const std::vector<Fan>& around) {
    boundary.clear();
    int outgoing = -1;
    for (const Fan& fan : around) {
      if (fan.closed) {
        // The last face around an inner vertex closed its fan; add_face leaves its halfedge there.
        const int last = *std::max_element(fan.corners.begin(), fan.corners.end());
        outgoing = halfedges.faceHalfedge[std::size_t(last)];
        continue;
      }
      const int in = halfedges.faceHalfedge[std::size_t(fan.corners.back())] ^ 1;
      const int first = fans.previousAt(fan.corners.front());
      boundary.emplace_back(in, halfedges.faceHalfedge[std::size_t(first)] ^ 1);
    }
    for (std::size_t i = 0; i < boundary.size(); ++i)
      out.set_next_halfedge_handle(HalfedgeHandle(boundary[i].first),
                                   HalfedgeHandle(boundary[(i + 1) % boundary.size()].second));
    if (!boundary.empty()) outgoing = boundary.front().second;
    if (outgoing >= 0) out.set_halfedge_handle(TriMesh::VertexHandle(v), HalfedgeHandle(outgoing));
  };
  for (int v = 0; v < int(points); ++v)
    link(v, fansAround(fans, v, seen));
  // A copy is the corner of one split-off face: one open fan.
  for (std::size_t i = 0; i < layout.copyOf.size(); ++i)
    link(int(points + i), {Fan{{layout.copyCorner[i]}, false}});
}

// OpenMesh's importer marks what it splits off so; the readers' callers may look.
void markSplitFaces(TriMesh& out, const Layout& layout) {
  for (std::size_t k = 0; k < layout.faces.size(); ++k) {
    if (!layout.split[k]) continue;
    const auto face = TriMesh::FaceHandle(int(k));
    out.status(face).set_fixed_nonmanifold(true);
    for (auto h : out.fh_range(face)) {
      out.status(out.edge_handle(h)).set_fixed_nonmanifold(true);
      out.status(out.to_vertex_handle(h)).set_fixed_nonmanifold(true);
    }
  }
}

}  // namespace

ImportCounts linkSoup(const PolygonSoup& soup, TriMesh& out) {
  ImportCounts counts;
  const std::size_t points = soup.points.size();
  const Triangles triangles = triangulate(soup, counts);
  Fans fans(triangles, points);
  {
    std::vector<char> seen(3 * triangles.corners.size(), 0);
    splitClosedFansOff(fans, points, seen);
  }
  const Layout layout = layOut(triangles, fans, points, counts);
  const Halfedges halfedges = numberEdges(layout);
  out.resize(points + layout.copyOf.size(), halfedges.edges(), layout.faces.size());
  for (std::size_t v = 0; v < points; ++v)
    out.set_point(TriMesh::VertexHandle(int(v)), soup.points[v]);
  for (std::size_t i = 0; i < layout.copyOf.size(); ++i)
    out.set_point(TriMesh::VertexHandle(int(points + i)),
                  soup.points[std::size_t(layout.copyOf[i])]);
  for (std::size_t h = 0; h < halfedges.to.size(); ++h) {
    out.set_vertex_handle(HalfedgeHandle(int(h)), TriMesh::VertexHandle(halfedges.to[h]));
    out.set_face_handle(HalfedgeHandle(int(h)), TriMesh::FaceHandle(halfedges.face[h]));
  }
  for (std::size_t k = 0; k < layout.faces.size(); ++k) {
    const int* h = halfedges.faceHalfedge.data() + 3 * k;
    out.set_halfedge_handle(TriMesh::FaceHandle(int(k)), HalfedgeHandle(h[2]));
    for (int i = 0; i < 3; ++i)
      out.set_next_halfedge_handle(HalfedgeHandle(h[i]), HalfedgeHandle(h[(i + 1) % 3]));
  }
  linkVertices(out, layout, halfedges, fans, points);
  markSplitFaces(out, layout);
  return counts;
}

}  // namespace geobrush::meshread
