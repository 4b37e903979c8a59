#include <memory>
#include <optional>
#include <string>

#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/stitch.hpp"

namespace {

using geobrush::Context;
using geobrush::Field2D;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::PasteMap;
using geobrush::Region2D;
using geobrush::StitchOutside;

// Every dab re-stitches into the same target: how the target canvas maps into its mesh (the
// stitch base) is derived data the framework keeps per target parameterization, its outside part
// shared by the canvases of a drag within one cell (derivedStitchBase). Every result starts as
// that outside (tens of megabytes on a large target): a result the framework has retired is
// recycled (Context::recycle) and turned back into it in place (restoreOutside, the border
// alone), and a retired paste map keeps its entries for the outside part; where there is none,
// the part is copied. Either way the result is the one a fresh node makes.
class StitchNode final : public geobrush::Node {
 public:
  // The paste's layout (stitchLayoutInto) needs the region and the canvases alone: the evaluator
  // runs it while the membrane is solved and the cages warp the draft.
  void prepare(Context& ctx) override {
    laid_.reset();
    const auto region = ctx.in<Region2D>("region");
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    if (region->empty()) ctx.warn("the region is empty: the target is unchanged");
    try {
      const auto base = geobrush::derivedStitchBase(ctx, "target");
      const auto sameOutside = [&](const StitchOutside& made) {
        return &made == base->outside.get();
      };
      auto mesh = geobrush::recyclePasteOutside(ctx, "mesh", base->outside);
      const bool prepared = mesh != nullptr;
      if (!prepared) mesh = std::make_shared<Mesh>();
      auto map = ctx.recycle<PasteMap, StitchOutside>("map", sameOutside).value;
      if (!map) map = std::make_shared<PasteMap>();
      geobrush::StitchOptions options;
      options.seamRefinementRatio = ctx.param<double>("seam_refinement");
      geobrush::StitchResult result = geobrush::stitchLayoutInto(
          mesh->surface, *region, *source, *target, base.get(), prepared, options, std::move(*map));
      *map = std::move(result.map);
      laid_ = Laid{std::move(mesh), std::move(map), result.firstPatchVertex,
                   result.startsWithOutside ? base->outside : nullptr};
    } catch (const geobrush::StitchError& e) {
      throw NodeError::input("region", e.what());
    }
  }

  void compute(Context& ctx) override {
    if (!laid_) throw NodeError("the paste was not laid out before it was placed");
    const auto region = ctx.in<Region2D>("region");
    const auto source = ctx.in<Parameterization>("source");
    const auto draft = geobrush::draftOrZero(ctx);
    const auto offset = ctx.hasInput("offset") ? ctx.in<Field2D>("offset") : nullptr;
    if (offset && offset->grid != region->grid)
      throw NodeError::input("offset", "the membrane was solved on another grid than the region's");
    try {
      geobrush::requireDraftOf(draft->surface, *source);
    } catch (const geobrush::StitchError& e) {
      throw NodeError::input("draft", e.what());
    }
    Laid laid = std::move(*laid_);
    laid_.reset();
    try {
      geobrush::placePatch(laid.mesh->surface, *laid.map, *source, draft->surface, offset.get(),
                           laid.firstPatchVertex);
    } catch (const geobrush::StitchError& e) {
      throw NodeError::input("offset", e.what());
    }
    // A result that starts with the outside part can be turned back into it.
    if (laid.startsWith) {
      ctx.outRecyclable("mesh", std::move(laid.mesh), laid.startsWith);
      ctx.outRecyclable("map", std::move(laid.map), laid.startsWith);
    } else {
      ctx.out("mesh", std::move(laid.mesh));
      ctx.out("map", std::shared_ptr<const PasteMap>(std::move(laid.map)));
    }
  }

 private:
  struct Laid {
    std::shared_ptr<Mesh> mesh;  // the paste with R_in at the source canvas' positions
    std::shared_ptr<PasteMap> map;
    int firstPatchVertex = 0;
    std::shared_ptr<const StitchOutside> startsWith;  // the outside part it starts with, or null
  };
  std::optional<Laid> laid_;  // from prepare() to compute()
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.stitch", 1)
            .label("Stitch")
            .category("Real-time")
            .doc("Pastes R_in into the target (paper section 4.4, Fig. 6d): each source vertex v "
                 "goes to x~(E_s(v)) + G(v), the target faces inside Q are removed, and the gap "
                 "between the two outlines is triangulated in the parameter domain. The result is "
                 "one manifold mesh whose seam shares vertices; handles in R_in raise its genus.")
            .input<Region2D>("region", "Q with R_in and the covered target vertices.")
            .input<Parameterization>("source", "E_s: the source canvas and its map.")
            .optionalInput<Mesh>("draft",
                                 "G(P_s): the source canvas warped by the cages. Unconnected, "
                                 "G = 0: the membrane alone fills the region (hole filling).")
            .input<Parameterization>("target", "E_t: the target canvas, on the target mesh.")
            .optionalInput<Field2D>("offset",
                                    "The offset membrane x~ on the region's grid; without it the "
                                    "draft is pasted as it is.")
            .output<Mesh>("mesh", "The target mesh with the paste stitched in.")
            .output<PasteMap>("map",
                              "Where each result vertex came from (target or source "
                              "canvas) and the seam faces: the input of "
                              "geobrush.metrics.")
            .paramDouble("seam_refinement", 6.0,
                         "Refine the target along the seam first where its edges there are on "
                         "average more than this many times as long as the paste's outline edges "
                         "(a coarse target), so that the seam strips do not fold; 0 never "
                         "refines. Added vertices lie on the target's faces and map to neither "
                         "mesh. Lower values also refine moderately coarse targets, at a cost "
                         "on every dab (a few ms for a few hundred seam faces).")
            .range(0, 1e3)
            .prepares({"region", "source", "target"})
            .node<StitchNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
