#include <memory>
#include <stdexcept>
#include <string>

#include "emd_transfer.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/vertex_fields.hpp"

namespace {

using geobrush::NodeError;
using geobrush::VertexFields;

// The columns h1, h2, ... of `fields`, in order.
std::vector<const std::vector<double>*> modesOf(const VertexFields& fields) {
  std::vector<const std::vector<double>*> modes;
  for (const auto& name : fields.modeNames())
    modes.push_back(&fields.column(name));
  return modes;
}

class EmdTransferNode final : public geobrush::Node {
 public:
  void compute(geobrush::Context& ctx) override {
    const auto target = ctx.in<VertexFields>("target_modes");
    const auto sampled = ctx.in<VertexFields>("sampled");
    if (sampled->meshHash != target->meshHash || sampled->vertexCount != target->vertexCount)
      throw NodeError::input("sampled", "it lies on another mesh than input 'target_modes'");
    const auto* residue = target->find("r");
    if (!residue) throw NodeError::input("target_modes", "it has no residue field r (emd's)");
    const auto* region = sampled->find("region");
    if (!region) throw NodeError::input("sampled", "it has no field region (emd_correspond's)");
    geobrush::EmdTransferOptions options;
    options.gains = ctx.param<std::vector<double>>("gains");
    options.keepTarget = ctx.param<std::vector<double>>("keep_target");
    const auto targetModes = modesOf(*target);
    const auto sourceModes = modesOf(*sampled);
    if (options.gains.size() != sourceModes.size())
      throw NodeError::param("gains", "it has " + std::to_string(options.gains.size()) +
                                          " entries for " + std::to_string(sourceModes.size()) +
                                          " source modes (one gain a(k) per mode)");
    if (options.keepTarget.size() != targetModes.size())
      throw NodeError::param("keep_target", "it has " + std::to_string(options.keepTarget.size()) +
                                                " entries for " +
                                                std::to_string(targetModes.size()) +
                                                " target modes (one b(k) per mode)");
    geobrush::EmdTransferResult result =
        geobrush::transferSignal(targetModes, *residue, sourceModes, *region, options);
    auto signal = std::make_shared<VertexFields>(target->vertexCount, target->meshHash);
    signal->add("g_hat", std::move(result.signal));
    signal->add("detail", std::move(result.detail));
    signal->add("region", *region);
    ctx.out("signal", signal);
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.emd_transfer", 1)
            .label("EMD Transfer")
            .category("EMD Transfer")
            .doc("The transferred signal of EMD detail transfer, Eqs. 3-5: on Q_t, g^ = r^t + "
                 "sum b(k) h_k^t + sum a(k) H_k^s; elsewhere the target's own g. The gains a are "
                 "the equalizer (per scale, finest first); keep_target b = 1 keeps the target's "
                 "detail at that scale (Eq. 3, for a smooth target), 0 replaces it (Eq. 5, for a "
                 "detailed one). Cheap: moving a gain re-runs this and the reconstruction's solve.")
            .input<VertexFields>("target_modes", "emd's output on the target mesh: h1..hm, r.")
            .input<VertexFields>("sampled", "emd_correspond's output: H_k^s on Q_t, region.")
            .output<VertexFields>("signal",
                                  "Fields on the target mesh: g_hat, detail (the source's part, "
                                  "sum a(k) H_k^s), region (1 on Q_t).")
            .paramList("gains", 1, {1, 1, 1}, "a(k): one gain per source mode, finest first.")
            .paramList("keep_target", 1, {1, 1, 1},
                       "b(k): one per target mode; 1 keeps it (Eq. 3), 0 drops it (Eq. 5).")
            .node<EmdTransferNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
