#include <memory>
#include <string>

#include "geobrush/mesh.hpp"
#include "geobrush/node.hpp"
#include "geobrush/param.hpp"
#include "geobrush/registry.hpp"
#include "roi_correct.hpp"

namespace {

using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Strokes;
using geobrush::TriMesh;

class RoiCorrectNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto strokes = ctx.in<Strokes>("strokes");
    const auto source = ctx.in<Parameterization>("source");
    geobrush::RoiCorrectOptions options;
    options.includeProtrusions = ctx.param<bool>("include_protrusions");
    options.protrusionThreshold = ctx.param<double>("protrusion_threshold");
    options.ring = ctx.param<int>("ring");
    options.margin = ctx.param<double>("margin");
    geobrush::RoiCorrectResult result;
    try {
      // The flags depend on the source and the options they read alone: derived data, kept while
      // a brush paints.
      const geobrush::Hash flagOptions = geobrush::Hasher()
                                             .u64(options.includeProtrusions)
                                             .f64(options.protrusionThreshold)
                                             .u64(std::uint64_t(options.ring))
                                             .digest();
      const auto flags = ctx.derived("roi_correction_flags", {"source"}, flagOptions, [&] {
        return std::make_shared<const std::vector<std::uint8_t>>(
            geobrush::correctionFlags(*source, options));
      });
      result = geobrush::correctRoi(*strokes, *source, options, *flags);
    } catch (const geobrush::RoiCorrectError& e) {
      throw NodeError::input("source", e.what());
    }
    if (!result.settled)
      ctx.warn("the outline still cuts folded faces after the correction rounds; paint wider");
    if (!result.outlineFaces.empty()) {
      const auto& mesh = source->canvas->surface;
      const auto p = mesh.calc_face_centroid(TriMesh::FaceHandle(result.outlineFaces.front()));
      ctx.warn("the correction takes in folded faces up to the source canvas' outline (" +
               std::to_string(result.outlineFaces.size()) + " faces, near " +
               geobrush::formatParam(geobrush::Vec3{p[0], p[1], p[2]}) +
               "): the seam may fold there; grow the source canvas to take the whole feature");
    }
    ctx.out("strokes", std::make_shared<const Strokes>(std::move(result.strokes)));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.roi_correct", 1)
            .label("ROI Correction")
            .category("Real-time")
            .doc("Section 4.5 of the paper: where the outline of the painted region cuts faces "
                 "that the source map folds over, those faces and the flagged faces next to them "
                 "are taken in whole, by a dab slightly larger than their image appended to the "
                 "strokes. Optionally steep protruding features are flagged as well, so that "
                 "painting part of one takes all of it. Warns where the faces it takes in reach "
                 "the source canvas' outline: the region then ends inside folded geometry and "
                 "the seam there may fold.")
            .input<Strokes>("strokes", "The painted dabs.")
            .input<Parameterization>("source", "E_s with its reversed-face flags.")
            .output<Strokes>("strokes", "The dabs, with one more per feature taken in.")
            .paramBool("include_protrusions", false,
                       "Flag faces turning away from the DEM normal (below the threshold), grown "
                       "by the ring, instead of using the map's reversed flags.")
            .paramDouble("protrusion_threshold", 0.5,
                         "Face normal . DEM normal below which a face counts as protruding.")
            .range(-1, 1)
            .paramInt("ring", 3, "Rings of neighbouring faces a protruding face flags (k).")
            .range(0, 20)
            .paramDouble("margin", 0.1,
                         "How far an added dab reaches beyond the taken faces, relative to its "
                         "radius.")
            .range(0, 10)
            .node<RoiCorrectNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
