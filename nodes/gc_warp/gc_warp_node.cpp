#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "gc_warp.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/node.hpp"
#include "geobrush/region.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Cage;
using geobrush::Canvas;
using geobrush::Context;
using geobrush::GreenCoordinates;
using geobrush::Mesh;
using geobrush::NodeError;

// Computing the coordinates costs about 40 times as much as applying them (GeoBrush section
// 4.1), and moving the target cage must only re-apply them: they are derived data the framework
// keeps per canvas, source cage and epsilon, and a compute with only the target cage changed
// outputs the very same GreenCoordinates value.
class GcWarpNode final : public geobrush::Node {
 public:
  // The coordinates of the canvas in the source cage, with the warning they come with.
  struct Coordinates {
    std::shared_ptr<const GreenCoordinates> value;
    std::string outsideWarning;
  };

  static Coordinates coordinatesOf(Context& ctx, const Canvas& canvas,
                                   const std::shared_ptr<const Cage>& sourceCage, double epsilon) {
    std::vector<Eigen::Vector3d> points;
    points.reserve(canvas.surface.n_vertices());
    for (auto v : canvas.surface.vertices())
      points.push_back(geobrush::pointOf(canvas.surface, v));
    geobrush::GreenOptions options;
    options.epsilon = epsilon;
    options.progress = [&ctx](double fraction) {
      ctx.throwIfCancelled();
      ctx.progress(fraction);
    };
    geobrush::GreenCoordinatesResult result;
    try {
      result = geobrush::computeGreenCoordinates(sourceCage->mesh, points, options);
    } catch (const geobrush::CageError& e) {
      throw NodeError::input("source_cage", e.what());
    }
    Coordinates made;
    if (!result.outsidePoints.empty()) {
      made.outsideWarning = std::to_string(result.outsidePoints.size());
      made.outsideWarning += " canvas points (the first is vertex ";
      made.outsideWarning += std::to_string(result.outsidePoints.front());
      made.outsideWarning +=
          ") lie outside the source cage; Green coordinates do not reproduce them";
    }
    auto coordinates = std::make_shared<GreenCoordinates>();
    coordinates->cage = sourceCage;
    coordinates->phi = std::move(result.phi);
    coordinates->psi = std::move(result.psi);
    made.value = std::move(coordinates);
    return made;
  }

  void compute(Context& ctx) override {
    const auto canvas = ctx.in<Canvas>("canvas");
    const auto sourceCage = ctx.in<Cage>("source_cage");
    const auto targetCage = ctx.in<Cage>("target_cage");
    const double epsilon = ctx.param<double>("epsilon");
    const geobrush::Hash epsilonKey = geobrush::Hasher().f64(epsilon).digest();
    const auto derived =
        ctx.derived("green_coordinates", {"canvas", "source_cage"}, epsilonKey, [&] {
          return std::make_shared<const Coordinates>(
              coordinatesOf(ctx, *canvas, sourceCage, epsilon));
        });
    if (!derived->outsideWarning.empty()) ctx.warn(derived->outsideWarning);
    ctx.throwIfCancelled();
    const auto& coordinates = derived->value;

    ctx.out("coordinates", coordinates);
    try {
      if (ctx.hasInput("region")) {
        const auto region = ctx.in<geobrush::Region2D>("region");
        requireRegionOnCanvas(*region, *canvas);
        outPartialDraft(ctx, *canvas, coordinates, *sourceCage, *targetCage, region->draftSupport);
        return;
      }
      const auto warped = geobrush::applyGreenCoordinates(coordinates->phi, coordinates->psi,
                                                          sourceCage->mesh, targetCage->mesh);
      geobrush::TriMesh draft = canvas->surface;
      for (auto v : draft.vertices())
        setPoint(draft, v.idx(), warped[std::size_t(v.idx())]);
      ctx.out("draft", std::make_shared<const Mesh>(std::move(draft)));
    } catch (const geobrush::CageError& e) {
      throw NodeError::input("target_cage", e.what());
    }
  }

 private:
  static void requireRegionOnCanvas(const geobrush::Region2D& region, const Canvas& canvas) {
    try {
      geobrush::requireRegionOn(region, canvas.surface.n_vertices());
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("region", e.what());
    }
  }

  static void setPoint(geobrush::TriMesh& mesh, int v, const Eigen::Vector3d& p) {
    mesh.set_point(geobrush::TriMesh::VertexHandle(v), geobrush::toPoint(p));
  }

  // Which rows of a partial draft are warped, by which coordinates and for which target cage
  // (the framework's key of it); the others are at their source positions.
  struct Warped {
    std::shared_ptr<const GreenCoordinates> coordinates;
    geobrush::Hash targetCage = 0;
    std::vector<char> rows;
  };

  // The draft with only `rows` warped, the others at their source positions. A retired draft
  // warped by the same coordinates is recycled (Context::recycle): its rows warped for the same
  // target cage are kept, so a dab warps only the rows added since; rows that left the support,
  // or were warped for another cage, go back to their source positions, so the value depends on
  // the inputs alone.
  static void outPartialDraft(Context& ctx, const Canvas& canvas,
                              const std::shared_ptr<const GreenCoordinates>& coordinates,
                              const Cage& sourceCage, const Cage& targetCage,
                              const std::vector<int>& rows) {
    auto warped = std::make_shared<Warped>();
    warped->coordinates = coordinates;
    warped->targetCage = ctx.inputKeyOf("target_cage");
    const auto recycled = ctx.recycle<Mesh, Warped>(
        "draft", [&](const Warped& made) { return made.coordinates == coordinates; });
    std::shared_ptr<Mesh> draft = recycled.value;
    // A moved target cage: every row is warped anew.
    bool newCage = true;
    if (draft) {
      warped->rows = recycled.note->rows;
      newCage = recycled.note->targetCage != warped->targetCage;
    } else {
      draft = std::make_shared<Mesh>(canvas.surface);
      warped->rows.assign(canvas.surface.n_vertices(), 0);
    }
    std::vector<char> wanted(warped->rows.size(), 0);
    for (int row : rows)
      wanted[std::size_t(row)] = 1;
    for (std::size_t v = 0; v < wanted.size(); ++v)
      if (warped->rows[v] && (!wanted[v] || newCage)) {
        draft->surface.set_point(geobrush::TriMesh::VertexHandle(int(v)),
                                 canvas.surface.point(geobrush::TriMesh::VertexHandle(int(v))));
        warped->rows[v] = 0;
      }
    std::vector<int> missing;
    for (int row : rows)
      if (!warped->rows[std::size_t(row)]) missing.push_back(row);
    const auto points = geobrush::applyGreenCoordinates(coordinates->phi, coordinates->psi,
                                                        sourceCage.mesh, targetCage.mesh, missing);
    for (std::size_t k = 0; k < missing.size(); ++k) {
      setPoint(draft->surface, missing[k], points[k]);
      warped->rows[std::size_t(missing[k])] = 1;
    }
    ctx.outRecyclable("draft", std::move(draft), std::shared_ptr<const Warped>(std::move(warped)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.gc_warp", 1)
            .label("Green Coordinates Warp")
            .category("Preprocess")
            .doc("Deforms the canvas by Green coordinates (Lipman, Levin, Cohen-Or 2008) from the "
                 "source cage to the target cage: the draft geometry G(P_s). The coordinates are "
                 "kept between evaluations, so changing only the target cage re-applies them.")
            .input<Canvas>("canvas", "The canvas whose surface vertices are warped.")
            .input<Cage>("source_cage",
                         "Closed, outward-oriented cage around the canvas, in its rest pose.")
            .input<Cage>("target_cage",
                         "The same cage (same connectivity) moved to where the canvas should go.")
            .optionalInput<geobrush::Region2D>(
                "region",
                "When connected, only the vertices a paste of this region reads "
                "(its draft support) are warped; the others keep their source positions, and "
                "dragging the target canvas costs what the region needs.")
            .output<GreenCoordinates>("coordinates",
                                      "phi and psi of every canvas vertex in the source cage.")
            .output<Mesh>("draft", "The canvas surface with every vertex warped by the cages.")
            .paramDouble("epsilon", 1e-8,
                         "Points nearer a cage face than this fraction of the cage's size count as "
                         "on the cage and get their limits from inside.")
            .range(0, 1e-3)
            .node<GcWarpNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
