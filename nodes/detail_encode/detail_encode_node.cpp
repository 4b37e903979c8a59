#include <memory>

#include "detail_encode.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"

namespace {

using geobrush::Context;
using geobrush::NodeError;
using geobrush::Parameterization;

geobrush::DetailMethod detailMethod(const std::string& name) {
  if (name == "face_frame") return geobrush::DetailMethod::FaceFrame;
  if (name == "smooth_frame") return geobrush::DetailMethod::SmoothFrame;
  if (name == "normal_displacement") return geobrush::DetailMethod::NormalDisplacement;
  throw NodeError::param(
      "method", "expected face_frame, smooth_frame or normal_displacement, not '" + name + "'");
}

class DetailEncodeNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto feature = ctx.in<Parameterization>("feature");
    const auto base = ctx.in<Parameterization>("base");
    const geobrush::DetailMethod method = detailMethod(ctx.param<std::string>("method"));
    try {
      ctx.out("encoding", std::make_shared<const geobrush::DetailEncoding>(
                              geobrush::encodeDetail(feature, base, method)));
    } catch (const geobrush::DetailEncodeError& e) {
      throw NodeError::input(e.port(), e.what());
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("base", e.what());
    }
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.detail_encode", 1)
            .label("Detail Encode")
            .category("Cut and Paste")
            .doc("Encodes a feature F over its base B (topology-free cut and paste, Sec. 6.2): "
                 "each F vertex's uv is located in P^B, giving a face of B and barycentric "
                 "coordinates (clamped onto that face: where the uv falls outside every face, "
                 "or on a face the domain lays nearly flat, the offset takes up the rest), and "
                 "its offset from that base point is kept in the method's components. "
                 "F.boundary[i] sits on B's vertex i with offset 0.")
            .input<Parameterization>("feature", "P^F: uv per vertex of F (intrinsic_param).")
            .input<Parameterization>(
                "base", "P^B: uv per vertex of B over canvasOfMesh(B), in P^F's domain.")
            .output<geobrush::DetailEncoding>(
                "encoding", "Per F vertex: face of B, barycentric coordinates, offset.")
            .paramEnum("method", "smooth_frame",
                       {"smooth_frame", "face_frame", "normal_displacement"},
                       "smooth_frame: the offset's three components in a frame interpolated "
                       "over the face from its corners' normals and u directions (the default: "
                       "a frame that turns smoothly with the base, so a tall feature keeps its "
                       "shape where the moved base's faces change shape); face_frame: in the "
                       "base face's own frame (e1 along its first edge, n its normal; the "
                       "paper's, which jumps from face to face); normal_displacement: only the "
                       "height along B's interpolated normal (the baseline: tangential offsets "
                       "are lost).")
            .node<DetailEncodeNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
