#include <memory>
#include <stdexcept>
#include <string>

#include "emd.hpp"
#include "geobrush/canvas.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "geobrush/vertex_fields.hpp"

namespace {

using geobrush::Canvas;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::VertexFields;

geobrush::EmdOptions optionsOf(const geobrush::Context& ctx) {
  geobrush::EmdOptions options;
  options.modes = ctx.param<int>("modes");
  options.maxSift = ctx.param<int>("max_sift");
  options.sdStop = ctx.param<double>("sd_stop");
  options.envelope = ctx.param<std::string>("envelope") == "biharmonic"
                         ? geobrush::Envelope::biharmonic
                         : geobrush::Envelope::harmonic;
  return options;
}

std::shared_ptr<geobrush::Metrics> report(const geobrush::EmdResult& result) {
  auto metrics = std::make_shared<geobrush::Metrics>();
  metrics->values["modes_found"] = result.modesFound;
  for (std::size_t k = 0; k < result.reports.size(); ++k) {
    const std::string suffix = std::string("_h").append(std::to_string(k + 1));
    const auto& mode = result.reports[k];
    metrics->values["sifts" + suffix] = mode.sifts;
    metrics->values["maxima" + suffix] = mode.maxima;
    metrics->values["minima" + suffix] = mode.minima;
    metrics->values["sd" + suffix] = mode.lastSd;
    metrics->values["overshoot" + suffix] = mode.overshoot;
  }
  return metrics;
}

class EmdNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto mesh = ctx.in<Mesh>("mesh");
    const auto fields = ctx.in<VertexFields>("signal");
    if (const std::string why =
            fields->mismatch(mesh->surface, geobrush::derivedGeometryHash(ctx, mesh));
        !why.empty())
      throw NodeError::input("signal", why + " (of input 'mesh')");
    const std::string name = ctx.param<std::string>("field");
    const auto* signal = fields->find(name);
    if (!signal) throw NodeError::param("field", "input 'signal' has no field '" + name + "'");

    std::shared_ptr<const Canvas> canvas;
    if (ctx.hasInput("parameterization")) {
      canvas = ctx.in<geobrush::Parameterization>("parameterization")->canvas;
      if (!canvas || !canvas->source ||
          geobrush::derivedGeometryHash(ctx, canvas->source) != fields->meshHash)
        throw NodeError::input("parameterization",
                               "its canvas lies on another mesh than input "
                               "'mesh'");
    }
    geobrush::EmdResult result;
    try {
      result = canvas
                   ? geobrush::empiricalModeDecomposition(*canvas, *signal, optionsOf(ctx))
                   : geobrush::empiricalModeDecomposition(mesh->surface, *signal, optionsOf(ctx));
    } catch (const std::out_of_range& e) {
      throw NodeError(e.what());
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("signal", e.what());
    } catch (const std::runtime_error& e) {
      throw NodeError::input("mesh", e.what());
    }
    if (result.modesFound < int(result.modes.size()))
      ctx.warn("the signal has " + std::to_string(result.modesFound) +
               " intrinsic modes (too few extrema for more); the others are zero");

    auto modes = std::make_shared<VertexFields>(*fields);
    modes->columns.clear();
    for (std::size_t k = 0; k < result.modes.size(); ++k)
      modes->add(std::string("h").append(std::to_string(k + 1)), std::move(result.modes[k]));
    modes->add("r", std::move(result.residue));
    ctx.out("modes", modes);
    ctx.out("report", report(result));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(
      geobrush::NodeTypeBuilder("geobrush.emd", 1)
          .label("EMD")
          .category("EMD Transfer")
          .doc("Empirical mode decomposition of a field on a mesh (EMD detail transfer Eq. 2): "
               "g = h1 + ... + hm + r, finest scale first, by sifting after Wang et al. 2012: "
               "local extrema (above or below every neighbour, ties by vertex id), an envelope "
               "through the maxima and one through the minima, their mean subtracted until the "
               "change falls below sd_stop or max_sift sifts; each mode is then taken off and the "
               "rest sifted again. Offline: its output is cached while mesh and params stay.")
          .input<Mesh>("mesh", "The mesh the signal lies on.")
          .input<VertexFields>("signal", "Fields on that mesh (emd_signal's, or any).")
          .optionalInput<geobrush::Parameterization>(
              "parameterization",
              "Decompose on its canvas only (faster on a large mesh: the source's gdem or the "
              "target's dem); elsewhere the modes are zero and r is the signal.")
          .output<VertexFields>("modes", "Fields on the mesh: h1..hm, then r.")
          .output<geobrush::Metrics>(
              "report",
              "modes_found; per mode k: sifts_hk, maxima_hk, minima_hk (of the signal it started "
              "from), sd_hk (the last sift's change), overshoot_hk (most the signal left its "
              "envelopes by, relative to its range).")
          .paramString("field", "g", "The field of 'signal' to decompose.")
          .paramInt("modes", 3, "m: intrinsic modes before the residue.")
          .range(1, 16)
          .paramInt("max_sift", 10, "Sifts per mode at most.")
          .range(1, 1000)
          .paramDouble("sd_stop", 0.2,
                       "A mode ends when sum (s_prev - s)^2 / sum s_prev^2 falls below this.")
          .range(1e-6, 1.0)
          .paramEnum("envelope", "harmonic", {"harmonic", "biharmonic"},
                     "harmonic: L e = 0 between the extrema (bounded by them, kinked at them); "
                     "biharmonic: L M^-1 L e = 0 (smooth, may overshoot them; a wider stencil, "
                     "about 7 times slower: 15 s instead of 2 s for 100k vertices).")
          .node<EmdNode>()
          .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
