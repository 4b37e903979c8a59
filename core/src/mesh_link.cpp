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

// Which triangles are joined into one mesh, and each one's neighbour across each edge.
class Joins {
 public:
  Joins(const Triangles& triangles, std::size_t points)
      : triangles_(triangles), joined_(triangles.corners.size(), 1) {
    joinEdgesInOrder();
    listCornersOfVertices(points);
  }

  std::size_t triangles() const { return joined_.size(); }
  bool joined(std::size_t t) const { return joined_[t]; }
  void splitOff(std::size_t t) { joined_[t] = 0; }

  // Corners are numbered 3t + i: corner i of triangle t.
  int vertexAt(int corner) const {
    return triangles_.corners[std::size_t(corner / 3)][std::size_t(corner % 3)];
  }
  static int nextAt(int corner) { return corner - corner % 3 + (corner % 3 + 1) % 3; }
  static int previousAt(int corner) { return corner - corner % 3 + (corner % 3 + 2) % 3; }

  // The joined triangle on the other side of the edge that leaves `corner`, or -1.
  int across(int corner) const {
    const int t = across_[std::size_t(corner)];
    return t >= 0 && joined_[std::size_t(t)] ? t : -1;
  }
  // The corner at `v` of triangle t.
  int cornerOf(int t, int v) const {
    const auto& c = triangles_.corners[std::size_t(t)];
    return 3 * t + (c[0] == v ? 0 : c[1] == v ? 1 : 2);
  }
  // Around the corner's vertex: the corner of the joined triangle across the edge leaving it
  // (the next face around the vertex), or of the one across the edge into it; -1 at a boundary.
  int successor(int corner) const {
    const int t = across(corner);
    return t < 0 ? -1 : cornerOf(t, vertexAt(corner));
  }
  int predecessor(int corner) const {
    const int t = across(previousAt(corner));
    return t < 0 ? -1 : cornerOf(t, vertexAt(corner));
  }

  // Vertex v's corners in all triangles, in triangle order.
  const int* cornersBegin(int v) const {
    return &vertexCorner_[std::size_t(first_[std::size_t(v)])];
  }
  const int* cornersEnd(int v) const { return &vertexCorner_[0] + first_[std::size_t(v) + 1]; }

 private:
  // A triangle joins when none of its edges is run its way by a triangle before it.
  void joinEdgesInOrder() {
    const auto& corners = triangles_.corners;
    KeyIndex faceOf(3 * corners.size());
    const auto exact = [](int) { return true; };
    for (std::size_t t = 0; t < corners.size(); ++t) {
      const auto& c = corners[t];
      bool free = true;
      for (std::size_t i = 0; i < 3 && free; ++i)
        free = faceOf.find(key(c[i], c[(i + 1) % 3]), exact) < 0;
      joined_[t] = free;
      for (std::size_t i = 0; i < 3 && free; ++i)
        faceOf.insert(key(c[i], c[(i + 1) % 3]), int(t), exact);
    }
    across_.assign(3 * corners.size(), -1);
    for (std::size_t t = 0; t < corners.size(); ++t)
      for (std::size_t i = 0; i < 3 && joined_[t]; ++i)
        across_[3 * t + i] = faceOf.find(key(corners[t][(i + 1) % 3], corners[t][i]), exact);
  }

  void listCornersOfVertices(std::size_t points) {
    first_.assign(points + 1, 0);
    for (const auto& c : triangles_.corners)
      for (int v : c)
        ++first_[std::size_t(v) + 1];
    for (std::size_t v = 0; v < points; ++v)
      first_[v + 1] += first_[v];
    vertexCorner_.resize(3 * triangles_.corners.size() + 1);
    std::vector<int> filled(first_.begin(), first_.end() - 1);
    for (std::size_t t = 0; t < triangles_.corners.size(); ++t)
      for (std::size_t i = 0; i < 3; ++i)
        vertexCorner_[std::size_t(filled[std::size_t(triangles_.corners[t][i])]++)] =
            int(3 * t + i);
  }

  const Triangles& triangles_;
  std::vector<char> joined_;
  std::vector<int> across_;        // per corner
  std::vector<int> first_;         // vertex v's corners: vertexCorner_[first_[v], first_[v + 1])
  std::vector<int> vertexCorner_;  // one past the end too, so that cornersEnd stays in range
};

// The fans of joined triangles around a vertex: an open fan from its corner with no predecessor
// to its corner with no successor, a closed fan as a cycle. Walks reuse their arrays.
class FanWalker {
 public:
  struct Fan {
    std::size_t begin, end;  // its corners, in order around the vertex: corners()[begin, end)
    bool closed;
  };

  explicit FanWalker(const Joins& joins) : joins_(joins), seen_(3 * joins.triangles(), 0) {}

  void walk(int v) {
    corners_.clear();
    fans_.clear();
    const auto joinedCorner = [&](int c) { return joins_.joined(std::size_t(c / 3)); };
    for (const int* c = joins_.cornersBegin(v); c != joins_.cornersEnd(v); ++c)
      if (joinedCorner(*c) && joins_.predecessor(*c) < 0) follow(*c, false);
    for (const int* c = joins_.cornersBegin(v); c != joins_.cornersEnd(v); ++c)
      if (joinedCorner(*c) && !seen_[std::size_t(*c)]) follow(*c, true);
    for (int c : corners_)
      seen_[std::size_t(c)] = 0;
  }

  const std::vector<int>& corners() const { return corners_; }
  const std::vector<Fan>& fans() const { return fans_; }

 private:
  void follow(int start, bool closed) {
    const std::size_t begin = corners_.size();
    for (int c = start; c >= 0 && !seen_[std::size_t(c)]; c = joins_.successor(c)) {
      seen_[std::size_t(c)] = 1;
      corners_.push_back(c);
    }
    fans_.push_back({begin, corners_.size(), closed});
  }

  const Joins& joins_;
  std::vector<char> seen_;  // per corner; clear between walks
  std::vector<int> corners_;
  std::vector<Fan> fans_;
};

// OpenMesh can join a vertex's open fans, but not a closed fan with anything else.
void splitClosedFansOff(Joins& joins, std::size_t points) {
  FanWalker walker(joins);
  for (int v = 0; v < int(points); ++v) {
    walker.walk(v);
    const auto& fans = walker.fans();
    const auto& corners = walker.corners();
    if (fans.size() < 2 || std::none_of(fans.begin(), fans.end(), [](auto& f) { return f.closed; }))
      continue;
    // The fan of the vertex's first corner stays: its corners come in triangle order.
    const int first = *std::min_element(corners.begin(), corners.end());
    const auto kept = std::find_if(fans.begin(), fans.end(), [&](const auto& fan) {
      return std::find(corners.begin() + std::ptrdiff_t(fan.begin),
                       corners.begin() + std::ptrdiff_t(fan.end),
                       first) != corners.begin() + std::ptrdiff_t(fan.end);
    });
    for (auto fan = fans.begin(); fan != fans.end(); ++fan) {
      if (fan == kept || (!kept->closed && !fan->closed)) continue;
      for (std::size_t i = fan->begin; i < fan->end; ++i)
        joins.splitOff(std::size_t(corners[i] / 3));
    }
  }
}

// The mesh's faces: every joined or split-off triangle in order, split-off ones on copies of their
// corners, numbered after the file's vertices in order.
struct Layout {
  std::vector<std::array<int, 3>> faces;
  std::vector<int> copyOf;      // vertex (file vertices + i) copies file vertex copyOf[i]
  std::vector<int> copyCorner;  // and is the corner 3k + j of face k
};

Layout layOut(const Triangles& triangles, const Joins& joins, std::size_t points,
              ImportCounts& counts) {
  Layout layout;
  layout.faces.reserve(triangles.corners.size());
  for (std::size_t t = 0; t < triangles.corners.size(); ++t) {
    std::array<int, 3> face = triangles.corners[t];
    if (!joins.joined(t)) {
      if (counts.nonManifold++ == 0) counts.firstNonManifold = triangles.polygon[t];
      for (int j = 0; j < 3; ++j) {
        layout.copyOf.push_back(face[std::size_t(j)]);
        layout.copyCorner.push_back(int(3 * t) + j);
        face[std::size_t(j)] = int(points + layout.copyOf.size() - 1);
      }
    }
    layout.faces.push_back(face);
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

// Edges in the order the faces first use them, halfedge 2e running the way its first face runs
// it: an edge a joined face shares with a joined face before it is that face's edge.
Halfedges numberEdges(const Layout& layout, const Joins& joins) {
  Halfedges halfedges;
  halfedges.faceHalfedge.resize(3 * layout.faces.size());
  halfedges.to.reserve(3 * layout.faces.size());
  halfedges.face.reserve(3 * layout.faces.size());
  for (std::size_t k = 0; k < layout.faces.size(); ++k) {
    const auto& f = layout.faces[k];
    for (std::size_t i = 0; i < 3; ++i) {
      const int corner = int(3 * k + i), from = f[i], to = f[(i + 1) % 3];
      const int other = joins.joined(k) ? joins.across(corner) : -1;
      int h;
      if (other >= 0 && std::size_t(other) < k) {
        h = halfedges.faceHalfedge[std::size_t(joins.cornerOf(other, to))] ^ 1;
      } else {
        h = int(halfedges.to.size());
        halfedges.to.insert(halfedges.to.end(), {to, from});
        halfedges.face.insert(halfedges.face.end(), {-1, -1});
      }
      halfedges.faceHalfedge[std::size_t(corner)] = h;
      halfedges.face[std::size_t(h)] = int(k);
    }
  }
  return halfedges;
}

// Per vertex, its halfedge and the boundary's next links through it. The boundary runs in along
// each open fan's last edge and out along the next fan's first edge, so that circulating around
// the vertex passes every fan, as add_face links several fans.
class VertexLinker {
 public:
  VertexLinker(TriMesh& out, const Halfedges& halfedges) : out_(out), halfedges_(halfedges) {}

  void link(int v, const std::vector<int>& corners, const std::vector<FanWalker::Fan>& fans) {
    boundary_.clear();
    int outgoing = -1;
    for (const auto& fan : fans) {
      if (fan.closed) {
        // The last face around an inner vertex closed its fan; add_face leaves its halfedge there.
        const int last = *std::max_element(corners.begin() + std::ptrdiff_t(fan.begin),
                                           corners.begin() + std::ptrdiff_t(fan.end));
        outgoing = halfedgeOut(last);
        continue;
      }
      const int in = halfedgeOut(corners[fan.end - 1]) ^ 1;
      const int out = halfedgeOut(Joins::previousAt(corners[fan.begin])) ^ 1;
      boundary_.emplace_back(in, out);
    }
    for (std::size_t i = 0; i < boundary_.size(); ++i)
      out_.set_next_halfedge_handle(HalfedgeHandle(boundary_[i].first),
                                    HalfedgeHandle(boundary_[(i + 1) % boundary_.size()].second));
    if (!boundary_.empty()) outgoing = boundary_.front().second;
    if (outgoing >= 0) out_.set_halfedge_handle(TriMesh::VertexHandle(v), HalfedgeHandle(outgoing));
  }

 private:
  int halfedgeOut(int corner) const { return halfedges_.faceHalfedge[std::size_t(corner)]; }

  TriMesh& out_;
  const Halfedges& halfedges_;
  std::vector<std::pair<int, int>> boundary_;  // (in, out) of each open fan
};

void linkVertices(TriMesh& out, const Layout& layout, const Halfedges& halfedges,
                  const Joins& joins, std::size_t points) {
  VertexLinker linker(out, halfedges);
  FanWalker walker(joins);
  for (int v = 0; v < int(points); ++v) {
    walker.walk(v);
    linker.link(v, walker.corners(), walker.fans());
  }
  // A copy is the corner of one split-off face: one open fan.
  for (std::size_t i = 0; i < layout.copyOf.size(); ++i)
    linker.link(int(points + i), {layout.copyCorner[i]}, {FanWalker::Fan{0, 1, false}});
}

// OpenMesh's importer marks what it splits off so; the readers' callers may look.
void markSplitFaces(TriMesh& out, const Joins& joins) {
  for (std::size_t k = 0; k < joins.triangles(); ++k) {
    if (joins.joined(k)) continue;
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
  Joins joins(triangles, points);
  splitClosedFansOff(joins, points);
  const Layout layout = layOut(triangles, joins, points, counts);
  const Halfedges halfedges = numberEdges(layout, joins);
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
  linkVertices(out, layout, halfedges, joins, points);
  markSplitFaces(out, joins);
  return counts;
}

}  // namespace geobrush::meshread
