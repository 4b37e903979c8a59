#include "region_canvas.hpp"

#include <algorithm>

#include "geobrush/cut_paste.hpp"
#include "geobrush/face_selection.hpp"

namespace geobrush {
namespace {

std::vector<char> paintedFaces(const Strokes& strokes, const Parameterization& source) {
  const Canvas& canvas = *source.canvas;
  std::vector<char> in(canvas.surface.n_vertices(), 0);
  for (std::size_t v = 0; v < in.size(); ++v)
    in[v] = strokes.contains(source.uv[v]);
  std::vector<char> selected(canvas.surface.n_faces(), 0);
  for (auto f : canvas.surface.faces()) {
    bool all = true;
    for (auto v : canvas.surface.fv_range(f))
      all = all && in[std::size_t(v.idx())];
    selected[std::size_t(f.idx())] = all;
  }
  return selected;
}

// The piece holding the origin face, else the one with the most faces (ties: the lowest face).
std::vector<int> keptPiece(const TriMesh& surface, const std::vector<char>& selected,
                           int originFace) {
  if (originFace >= 0 && selected[std::size_t(originFace)])
    return connectedFaces(surface, originFace, selected);
  std::vector<char> seen(selected.size(), 0);
  std::vector<int> best;
  for (std::size_t f = 0; f < selected.size(); ++f) {
    if (!selected[f] || seen[f]) continue;
    std::vector<int> piece = connectedFaces(surface, int(f), selected);
    for (int g : piece)
      seen[std::size_t(g)] = 1;
    if (piece.size() > best.size()) best = std::move(piece);
  }
  return best;
}

std::size_t countSelected(const std::vector<char>& selected) {
  return std::size_t(std::count(selected.begin(), selected.end(), char(1)));
}

}  // namespace

RegionCanvasResult regionCanvas(const Strokes& strokes, const Parameterization& source) {
  const Canvas& canvas = *source.canvas;
  if (!canvas.source || canvas.sourceFace.size() != canvas.surface.n_faces() ||
      source.uv.size() != canvas.surface.n_vertices())
    throw std::invalid_argument("the source canvas does not say which mesh faces it holds");
  const TriMesh& surface = canvas.surface;
  std::vector<char> selected = paintedFaces(strokes, source);
  const std::size_t painted = countSelected(selected);
  if (painted == 0) throw std::invalid_argument("the strokes paint no whole source face");
  removePinches(surface, selected, selectedFaces(selected));
  std::vector<int> piece = keptPiece(surface, selected, canvas.originFace);
  if (piece.empty()) throw std::invalid_argument("the region has no face left that forms a disc");
  std::vector<char> kept(selected.size(), 0);
  for (int f : piece)
    kept[std::size_t(f)] = 1;
  fillEnclosed(surface, kept, -1);
  removePinches(surface, kept, selectedFaces(kept));
  piece = keptPiece(surface, kept, canvas.originFace);

  RegionCanvasResult result;
  std::vector<int> sourceFaces;
  std::size_t fromRegion = 0;
  for (int f : piece) {
    sourceFaces.push_back(canvas.sourceFace[std::size_t(f)]);
    fromRegion += selected[std::size_t(f)];
  }
  result.enclosed = piece.size() - fromRegion;
  result.dropped = painted - fromRegion;
  const bool originKept = std::binary_search(piece.begin(), piece.end(), canvas.originFace);
  const int originFace = originKept ? canvas.originFace : piece.front();
  Eigen::Vector3d originPoint = canvas.originPoint;
  if (!originKept) {
    originPoint = Eigen::Vector3d::Zero();
    for (auto v : surface.fv_range(TriMesh::FaceHandle(originFace)))
      originPoint += Eigen::Vector3d(surface.point(v).data()) / 3.0;
  }
  result.feature = canvasFromFaces(canvas.source, sourceFaces,
                                   canvas.sourceFace[std::size_t(originFace)], originPoint);
  return result;
}

}  // namespace geobrush
