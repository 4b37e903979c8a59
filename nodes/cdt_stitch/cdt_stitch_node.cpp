#include <memory>

#include "cdt_stitch.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/stitch.hpp"

namespace {

using geobrush::Context;
using geobrush::Field2D;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Region2D;
using geobrush::StitchOutside;

// What the target's pastes share (how its canvas sits in its mesh, the locator, the part outside
// the open faces) is the stitch base, derived data the framework keeps per target. A result that
// starts with the base's outside part is published as recyclable: once the framework retires it,
// a later paste into the same outside turns it back into that part in place (restoreOutside)
// instead of copying the part, the size of the target, again. The result is a fresh node's.
class CdtStitchNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto region = ctx.in<Region2D>("region");
    const auto source = ctx.in<Parameterization>("source");
    const auto target = ctx.in<Parameterization>("target");
    const auto draft = geobrush::draftOrZero(ctx);
    const auto offset = ctx.hasInput("offset") ? ctx.in<Field2D>("offset") : nullptr;
    if (offset && offset->grid != region->grid)
      throw NodeError::input("offset", "the membrane was solved on another grid than the region's");
    if (region->empty()) ctx.warn("the region is empty: the target is unchanged");
    geobrush::CdtStitchOptions options;
    options.minAngleDegrees = ctx.param<double>("min_angle_deg");
    options.maxArea = ctx.param<double>("max_area");
    options.splitBoundary = ctx.param<bool>("split_boundary");
    std::shared_ptr<Mesh> mesh;
    std::shared_ptr<const StitchOutside> outside;
    geobrush::CdtStitchResult result;
    try {
      const auto base = geobrush::derivedStitchBase(ctx, "target");
      outside = base->outside;
      mesh = geobrush::recyclePasteOutside(ctx, "mesh", outside);
      const bool recycled = mesh != nullptr;
      if (!recycled) mesh = std::make_shared<Mesh>();
      result = geobrush::cdtStitchPasteInto(mesh->surface, *region, *source, draft->surface,
                                            offset.get(), *target, base.get(), options, recycled);
    } catch (const geobrush::StitchError& e) {
      throw NodeError::input("target", e.what());
    } catch (const geobrush::CdtStitchError& e) {
      if (e.port() == "min_angle_deg" || e.port() == "max_area")
        throw NodeError::param(e.port(), e.what());
      throw NodeError::input(e.port(), e.what());
    }
    if (result.paste.startsWithOutside)
      ctx.outRecyclable("mesh", std::move(mesh), outside);
    else
      ctx.out("mesh", std::move(mesh));
    ctx.out("map", std::make_shared<const geobrush::PasteMap>(std::move(result.paste.map)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.cdt_stitch", 1)
            .label("CDT stitch")
            .category("Real-time")
            .doc("Pastes R_in into the target as geobrush.stitch does, but closes the gap between "
                 "the target hole's outline and R_in's with a constrained Delaunay triangulation "
                 "in the domain (GPU texture cloning paper), refined by CGAL to a minimum angle "
                 "and a maximum area; unless split_boundary, no point goes on either outline and "
                 "the bounds hold where the outlines allow. Added points lie on the target surface "
                 "plus an offset "
                 "harmonic over the gap (R_in's offset from the target on its outline, 0 on the "
                 "hole's).")
            .input<Region2D>("region", "Q with R_in and the covered target vertices.")
            .input<Parameterization>("source", "E_s: the source canvas and its map.")
            .optionalInput<Mesh>("draft",
                                 "G(P_s): the source canvas warped. Unconnected, G = 0: the "
                                 "offset alone fills the region.")
            .input<Parameterization>("target", "E_t: the target canvas, on the target mesh.")
            .optionalInput<Field2D>("offset",
                                    "The offset membrane x~ on the region's grid; without it the "
                                    "draft is pasted as it is.")
            .output<Mesh>("mesh", "The target mesh with the paste and the triangulated gap.")
            .output<geobrush::PasteMap>("map",
                                        "Where each result vertex came from (target, source "
                                        "canvas, or neither for the gap's added points) and the "
                                        "gap's faces as seam faces.")
            .paramDouble("min_angle_deg", 20.0,
                         "The smallest angle of a gap triangle, where the outlines allow it; "
                         "CGAL's refinement is proven to end up to about 20.7 degrees.")
            .range(0, 30)
            .paramDouble("max_area", 0.0,
                         "The largest area of a gap triangle in the domain; 0: (sqrt 3 / 4) e^2, "
                         "e the mean outline edge length in the domain.")
            .range(0, 1e12)
            .paramBool("split_boundary", false,
                       "Let the refinement split encroached outline edges, and the kept or "
                       "pasted face beside each with it, so that the bounds hold everywhere; "
                       "the added outline points map to neither mesh.")
            .node<CdtStitchNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
