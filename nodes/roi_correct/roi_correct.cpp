#include "roi_correct.hpp"

#include <algorithm>
#include <cmath>

#include "geobrush/exponential_map.hpp"

namespace geobrush {
namespace {

void checkInputs(const Parameterization& source, const RoiCorrectOptions& options) {
  if (!source.canvas || source.uv.size() != source.canvas->surface.n_vertices())
    throw RoiCorrectError("the source parameterization does not match its canvas");
  if (!(options.margin >= 0) || options.ring < 0 || options.maxRounds < 1)
    throw RoiCorrectError("margin, ring and rounds must be >= 0, >= 0 and >= 1");
}

}  // namespace

std::vector<std::uint8_t> correctionFlags(const Parameterization& source,
                                          const RoiCorrectOptions& options) {
  checkInputs(source, options);
  const TriMesh& mesh = source.canvas->surface;
  if (options.includeProtrusions) {
    return growFaceRing(mesh, reversedFaces(mesh, source.normal, options.protrusionThreshold),
                        options.ring);
  }
  if (source.reversedFaces.empty()) return std::vector<std::uint8_t>(mesh.n_faces(), 0);
  if (source.reversedFaces.size() != mesh.n_faces())
    throw RoiCorrectError("the reversed flags do not match the canvas faces");
  return source.reversedFaces;
}

namespace {

// Flagged faces whose corners lie on both sides of the outline of Q.
std::vector<int> crossedFaces(const TriMesh& mesh, const std::vector<std::uint8_t>& flagged,
                              const std::vector<char>& inQ) {
  std::vector<int> crossed;
  for (auto f : mesh.faces()) {
    if (!flagged[std::size_t(f.idx())]) continue;
    int inside = 0, count = 0;
    for (auto v : mesh.fv_range(f)) {
      inside += inQ[std::size_t(v.idx())];
      ++count;
    }
    if (inside > 0 && inside < count) crossed.push_back(f.idx());
  }
  return crossed;
}

// The flagged faces edge-connected to `seed`, marked in `taken`.
std::vector<int> flaggedComponent(const TriMesh& mesh, const std::vector<std::uint8_t>& flagged,
                                  int seed, std::vector<char>& taken) {
  std::vector<int> component{seed};
  taken[std::size_t(seed)] = 1;
  for (std::size_t next = 0; next < component.size(); ++next)
    for (auto g : mesh.ff_range(TriMesh::FaceHandle(component[next])))
      if (flagged[std::size_t(g.idx())] && !taken[std::size_t(g.idx())]) {
        taken[std::size_t(g.idx())] = 1;
        component.push_back(g.idx());
      }
  return component;
}

// A disc around the uv image of `faces`: centred on their corners' mean, reaching the farthest
// corner plus the margin.
Dab enclosingDab(const TriMesh& mesh, const std::vector<Eigen::Vector2d>& uv,
                 const std::vector<int>& faces, double margin) {
  std::vector<int> corners;
  for (int f : faces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      corners.push_back(v.idx());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (int v : corners)
    centre += uv[std::size_t(v)];
  centre /= double(corners.size());
  double radius = 0;
  for (int v : corners)
    radius = std::max(radius, (uv[std::size_t(v)] - centre).norm());
  return {centre, radius * (1 + margin), false};
}

// The faces of `faces` (ascending) with a corner on the canvas' outline.
std::vector<int> facesAtOutline(const TriMesh& mesh, const std::vector<int>& faces) {
  std::vector<int> atOutline;
  for (int f : faces)
    for (auto v : mesh.fv_range(TriMesh::FaceHandle(f)))
      if (mesh.is_boundary(v)) {
        atOutline.push_back(f);
        break;
      }
  return atOutline;
}

}  // namespace

RoiCorrectResult correctRoi(const Strokes& strokes, const Parameterization& source,
                            const RoiCorrectOptions& options) {
  return correctRoi(strokes, source, options, correctionFlags(source, options));
}

RoiCorrectResult correctRoi(const Strokes& strokes, const Parameterization& source,
                            const RoiCorrectOptions& options,
                            const std::vector<std::uint8_t>& flagged) {
  checkInputs(source, options);
  const TriMesh& mesh = source.canvas->surface;
  if (flagged.size() != mesh.n_faces())
    throw RoiCorrectError("the correction flags do not match the canvas faces");
  // Only corners of flagged faces decide anything: Q is tested there alone.
  std::vector<int> corners;
  for (auto f : mesh.faces())
    if (flagged[std::size_t(f.idx())])
      for (auto v : mesh.fv_range(f))
        corners.push_back(v.idx());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());

  RoiCorrectResult result;
  result.strokes.dabs = strokes.dabs;
  std::vector<char> taken(mesh.n_faces(), 0);
  std::vector<char> inQ(mesh.n_vertices(), 0);
  for (int round = 0; round < options.maxRounds; ++round) {
    for (int v : corners)
      inQ[std::size_t(v)] = result.strokes.contains(source.uv[std::size_t(v)]);
    const std::vector<int> crossed = crossedFaces(mesh, flagged, inQ);
    if (crossed.empty()) {
      result.outlineFaces = facesAtOutline(mesh, result.addedFaces);
      return result;
    }
    for (int seed : crossed) {
      if (taken[std::size_t(seed)]) continue;
      const std::vector<int> component = flaggedComponent(mesh, flagged, seed, taken);
      result.strokes.dabs.push_back(enclosingDab(mesh, source.uv, component, options.margin));
      result.addedFaces.insert(result.addedFaces.end(), component.begin(), component.end());
      ++result.featuresAdded;
    }
    std::sort(result.addedFaces.begin(), result.addedFaces.end());
  }
  result.settled = false;
  result.outlineFaces = facesAtOutline(mesh, result.addedFaces);
  return result;
}

}  // namespace geobrush
