#include <algorithm>
#include <memory>
#include <vector>

#include "geobrush/mesh.hpp"
#include "geobrush/mesh_points.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "handle_edit.hpp"

namespace {

using geobrush::Context;
using geobrush::Hasher;
using geobrush::Mesh;
using geobrush::NodeError;

// What the edits need of the unedited template, all derived data: its kNN graph (under a generic
// name, so that other nodes on the same template and k share it), D(x, L), each edit's region and
// the non-rigid handle's field (so that a drag of a rigid edit does not solve it again).
struct Derived {
  std::shared_ptr<const geobrush::KnnGraph> graph;
  std::shared_ptr<const geobrush::BoundaryDistances> boundary;
  std::vector<std::shared_ptr<const geobrush::HandleRegion>> regions;
  std::shared_ptr<const geobrush::NonrigidHandleField> nonrigid;
};

// The non-rigid field's key: k, the shape function and every move.
geobrush::Hash nonrigidKey(const geobrush::HandleEditOptions& options) {
  Hasher key;
  key.u64(std::uint64_t(options.k)).u64(std::uint64_t(options.profile.profile));
  key.u64(options.profile.samples.size());
  for (double sample : options.profile.samples)
    key.f64(sample);
  for (const geobrush::HandleVertexMove& move : options.nonrigid)
    for (int c = 0; c < 3; ++c)
      key.f64(move.point[c]).f64(move.translation[c]);
  return key.digest();
}

Derived derived(Context& ctx, const std::shared_ptr<const Mesh>& tmpl,
                const geobrush::HandleEditOptions& options) {
  const int k = options.k;
  Derived d;
  d.graph = geobrush::derivedVertexGraph(ctx, "template", k);
  d.boundary = ctx.derived("handle_edit_boundary", {"template"}, Hasher().u64(k).digest(), [&] {
    return std::make_shared<const geobrush::BoundaryDistances>(
        geobrush::boundaryDistances(tmpl->surface, *d.graph));
  });
  for (const geobrush::HandleEdit& edit : options.edits) {
    Hasher where;
    where.u64(k).f64(edit.point.x()).f64(edit.point.y()).f64(edit.point.z()).f64(edit.radius);
    d.regions.push_back(ctx.derived("handle_edit_region", {"template"}, where.digest(), [&] {
      return std::make_shared<const geobrush::HandleRegion>(
          geobrush::handleRegion(tmpl->surface, *d.graph, *d.boundary, edit.point, edit.radius));
    }));
  }
  d.nonrigid = ctx.derived("handle_edit_nonrigid", {"template"}, nonrigidKey(options), [&] {
    return std::make_shared<const geobrush::NonrigidHandleField>(geobrush::nonrigidHandleField(
        tmpl->surface, *d.graph, *d.boundary, options.nonrigid, options.profile));
  });
  return d;
}

// The profile param, or with "custom" the shape its samples draw.
geobrush::HandleShape shapeOf(Context& ctx) {
  const auto profile = geobrush::parseHandleProfile(ctx.param<std::string>("profile"));
  auto samples = ctx.param<std::vector<double>>("profile_samples");
  if (profile == geobrush::HandleProfile::Custom) return geobrush::customShape(std::move(samples));
  if (!samples.empty()) ctx.warn("profile_samples are read only with profile=custom");
  return profile;
}

// A drag re-evaluates this node with only the last edit's T changed. The kNN graph, D(x, L) and
// each edit's region (H and D(x, H)) are derived data of the unedited template, so the drag finds
// them all and costs a copy of the template's points and one blend per edit. Copying a whole
// template (its halfedges: tens of megabytes of fresh pages) would cost more than the rest, so a
// retired result of this node copied from an equal template (Context::recycle) has the
// template's points copied back into it: a fresh copy's result, bit for bit.
class HandleEditNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    try {
      const auto tmpl = ctx.in<Mesh>("template");
      geobrush::HandleEditOptions options;
      options.k = ctx.param<int>("k");
      options.profile = shapeOf(ctx);
      options.edits = geobrush::editsFromRows(ctx.param<std::vector<double>>("edits"));
      options.nonrigid = geobrush::movesFromRows(ctx.param<std::vector<double>>("nonrigid_handle"));
      const Derived d = derived(ctx, tmpl, options);
      std::vector<const geobrush::HandleRegion*> pointers;
      for (const auto& region : d.regions)
        pointers.push_back(region.get());
      const auto edited = copyOf(ctx, tmpl);
      const auto report = geobrush::applyHandleEdits(tmpl->surface, edited->surface, pointers,
                                                     options, d.nonrigid.get());
      ctx.outRecyclable("template", edited,
                        std::make_shared<const CopiedFrom>(CopiedFrom{ctx.inputKeyOf("template")}));
      auto metrics = std::make_shared<geobrush::Metrics>();
      metrics->values = {{"handles", report.handles},
                         {"vertices_moved", report.verticesMoved},
                         {"max_displacement", report.maxDisplacement},
                         {"nonrigid_vertices", double(d.nonrigid->handle.size())},
                         {"nonrigid_condition_number", d.nonrigid->conditionNumber}};
      ctx.out("report", std::move(metrics));
    } catch (const geobrush::HandleEditError& e) {
      if (e.option() == "template") throw NodeError::input(e.option(), e.what());
      throw NodeError::param(e.option(), e.what());
    }
  }

 private:
  // What a result was copied from: the framework's key of the template.
  struct CopiedFrom {
    geobrush::Hash templateKey = 0;
  };

  static std::shared_ptr<Mesh> copyOf(Context& ctx, const std::shared_ptr<const Mesh>& tmpl) {
    const geobrush::Hash key = ctx.inputKeyOf("template");
    const auto recycled = ctx.recycle<Mesh, CopiedFrom>(
        "template", [&](const CopiedFrom& from) { return from.templateKey == key; });
    if (!recycled) return std::make_shared<Mesh>(*tmpl);
    geobrush::copyPoints(tmpl->surface, recycled.value->surface);
    return recycled.value;
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.handle_edit", 1)
            .label("Handle Edit")
            .category("Inpainting")
            .doc("Free-form edits of a template by rigid handles and a non-rigid one (Freeform "
                 "surface inpainting, section 5): x_new = alpha T x + (1 - alpha) x, or x + "
                 "alpha d_h(x) with d_h the non-rigid handle's translations carried over by "
                 "Eqs. 4-6; alpha = profile(D(x,H) / (D(x,H) + D(x,L))) (Eq. 7), D the "
                 "kNN-graph distance, H the handle, L the template's boundary, which stays "
                 "fixed. Edits are rows, so a modelling session replays headless; every row's "
                 "distances are those of the unedited template.")
            .input<Mesh>("template", "The template to edit; it must have a boundary.")
            .output<Mesh>("template", "The edited template: the same connectivity, moved points.")
            .output<geobrush::Metrics>("report",
                                       "handles, vertices_moved, max_displacement (the "
                                       "largest distance of a point from its input position), "
                                       "nonrigid_vertices and nonrigid_condition_number.")
            .paramInt("k", 8, "Neighbours per vertex in the symmetric kNN graph (section 5.1).")
            .range(1, 64)
            .paramEnum("profile", "smoothstep", geobrush::handleProfileNames(),
                       "The shape function alpha(t): smoothstep 1 - 3t^2 + 2t^3, linear 1 - t, "
                       "cosine (1 + cos(pi t)) / 2, or custom (profile_samples).")
            .paramList("profile_samples", 1, {},
                       "With profile=custom: alpha at t = 0, 1/(m-1), ..., 1, joined by straight "
                       "lines; the first 1 (the handle moves by T), the last 0 (L stays).")
            .paramList("edits", int(geobrush::kEditRowSize), {},
                       "Edits as rows of px, py, pz, radius, tx, ty, tz, ax, ay, az, angle_deg, "
                       "applied in order: H is the vertices within graph distance radius of the "
                       "vertex nearest p; T turns by angle_deg about the axis a through that "
                       "vertex (where earlier rows moved it), then translates by t.")
            .paramList("nonrigid_handle", int(geobrush::kMoveRowSize), {},
                       "A non-rigid handle, applied after the edits, as rows of px, py, pz, tx, "
                       "ty, tz: the vertex nearest p moves by t; H is those vertices, and the "
                       "translations are carried over the template by Gaussian RBFs of the graph "
                       "distance, t_max the mean distance from H to L.")
            .node<HandleEditNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
