#include <algorithm>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <string>

#include "geobrush/domain_locator.hpp"
#include "geobrush/node.hpp"
#include "geobrush/registry.hpp"
#include "geobrush/values.hpp"
#include "membrane.hpp"
#include "membrane_boundary.hpp"
#include "membrane_vulkan.hpp"

namespace {

using geobrush::Context;
using geobrush::Field2D;
using geobrush::Mesh;
using geobrush::NodeError;
using geobrush::Parameterization;
using geobrush::Region2D;

// The kernel the `kernel` param asks for. "auto" is the CPU kernel on every device: the Vulkan
// passes make one submission per smoothed level, and that round trip costs more than the CPU's
// pass on lavapipe and on a discrete GPU alike (BENCHMARKS.md, "Vulkan on a GPU").
geobrush::MembraneKernel chooseKernel(const std::string& choice) {
  if (choice == "auto" || choice == "cpu") return geobrush::MembraneKernel::Cpu;
  if (choice != "vulkan")
    throw NodeError::param("kernel", "'" + choice + "' is not one of: auto, cpu, vulkan");
  const geobrush::MembraneVulkanDevice device = geobrush::membraneVulkanDevice();
  if (!device.available)
    throw NodeError::param(
        "kernel", "vulkan needs a Vulkan device, and there is none: " + device.unavailableReason);
  return geobrush::MembraneKernel::Vulkan;
}

// "kernel: cpu", or "kernel: vulkan (<device name>)".
std::string kernelNote(geobrush::MembraneKernel kernel) {
  std::string note = "kernel: ";
  note += geobrush::membraneKernelName(kernel);
  if (kernel == geobrush::MembraneKernel::Vulkan) {
    note += " (";
    note += geobrush::membraneVulkanDevice().name;
    note += ")";
  }
  return note;
}

// Each dab changes Q a little; the canvases' locators are derived data the framework keeps.
class MembraneNode final : public geobrush::Node {
 public:
  void compute(Context& ctx) override {
    const auto region = ctx.in<Region2D>("region");
    const auto source = ctx.in<Parameterization>("source");
    const auto draft = geobrush::draftOrZero(ctx);
    const auto target = ctx.in<Parameterization>("target");
    const auto continuity = ctx.param<bool>("derivative_constraints")
                                ? geobrush::MembraneContinuity::C1
                                : geobrush::MembraneContinuity::C0;
    const geobrush::MembraneKernel kernel = chooseKernel(ctx.param<std::string>("kernel"));
    auto field = std::make_shared<Field2D>();
    field->grid = region->grid;
    field->values.assign(region->grid.nodeCount(), Eigen::Vector3d::Zero());
    field->defined.assign(region->grid.nodeCount(), 0);
    auto report = std::make_shared<geobrush::Metrics>();
    if (std::find(region->inside.begin(), region->inside.end(), 1) == region->inside.end()) {
      report->notes.push_back("the region is empty: nothing to solve");
      ctx.out("offset", std::move(field));
      ctx.out("report", std::move(report));
      return;
    }
    // Both canvases' locators stay while the canvases do (a target drag keeps the source's).
    const auto sourceLocator = geobrush::derivedLocator(ctx, "source");
    const auto targetLocator = geobrush::derivedLocator(ctx, "target");
    geobrush::MembraneSetup setup;
    try {
      geobrush::requireRegionOn(*region, source->uv.size());
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("region", e.what());
    }
    try {
      setup = geobrush::membraneSetup(*region, *source, draft->surface, *sourceLocator,
                                      *targetLocator, continuity);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("draft", e.what());
    }
    geobrush::MembraneOptions options;
    options.tolerance = ctx.param<double>("tolerance");
    options.maxIterations = ctx.param<int>("max_iterations");
    options.kernel = kernel;
    geobrush::MembraneResult result;
    try {
      result = geobrush::solveMembrane(setup.problem, options);
    } catch (const std::invalid_argument& e) {
      throw NodeError::input("region", e.what());
    } catch (const std::runtime_error& e) {
      // A failing device call of the Vulkan kernel.
      if (kernel != geobrush::MembraneKernel::Vulkan) throw;
      throw NodeError::param("kernel", e.what());
    }
    if (!result.converged) {
      std::ostringstream message;
      message << "the membrane did not reach the tolerance " << options.tolerance << " within "
              << result.iterations << " iterations (relative residual " << result.residual << ")";
      throw NodeError(message.str());
    }
    report->values = {{"iterations", result.iterations},
                      {"relative_residual", result.residual},
                      {"unknowns", result.unknowns},
                      {"levels", result.levels}};
    report->notes.push_back(kernelNote(result.kernel));
    ctx.out("offset", std::make_shared<const Field2D>(
                          geobrush::membraneField(*region, setup, result.values)));
    ctx.out("report", std::move(report));
  }
};

void registerNodes(geobrush::PluginRegistrar& r) {
  r.add(geobrush::NodeTypeBuilder("geobrush.membrane", 1)
            .label("Offset Membrane")
            .category("Real-time")
            .doc("The C1 offset membrane x~ of the paper (section 4.4, Eqs. 4-5): on the "
                 "region's grid, the biharmonic function that equals R_out - g_in outside Q, value "
                 "and slope, so that g_in + x~ meets the target smoothly. Solved by conjugate "
                 "gradients with a Galerkin multigrid preconditioner from a nested-iteration "
                 "start. The preconditioner's stencil kernels run on the CPU or as Vulkan "
                 "compute passes, one submission per smoothed level; auto picks the CPU kernel, "
                 "faster than those round trips on lavapipe and on a discrete GPU.")
            .input<Region2D>("region", "Q on its grid, with R_in.")
            .input<Parameterization>("source", "E_s: the source canvas and its map.")
            .optionalInput<Mesh>("draft",
                                 "G(P_s): the source canvas warped by the cages. Unconnected, "
                                 "G = 0: the membrane alone fills the region (hole filling).")
            .input<Parameterization>("target", "E_t: the target canvas in the same domain.")
            .output<Field2D>("offset", "x~ on the region's grid.")
            .output<geobrush::Metrics>(
                "report",
                "The solve: CG iterations, relative residual, unknowns, "
                "multigrid levels and the kernel that ran (and the Vulkan device it ran on).")
            .paramBool("derivative_constraints", true,
                       "On: biharmonic with value and slope fixed (C1). Off: harmonic with the "
                       "value only (C0), the paper's Fig. 10 comparison.")
            .paramDouble("tolerance", 1e-6,
                         "Estimated relative error (energy norm) at which the solve stops.")
            .range(1e-12, 1e-2)
            .paramInt("max_iterations", 100, "Conjugate-gradient iterations at most.")
            .range(1, 10000)
            .paramEnum("kernel", "auto", {"auto", "cpu", "vulkan"},
                       "Where the multigrid's smoother and residuals run: vulkan (the Vulkan "
                       "device, an error without one), cpu, or auto (cpu, the faster on every "
                       "device measured). The two agree within the tolerance.")
            .node<MembraneNode>()
            .build());
}

}  // namespace

GEOBRUSH_PLUGIN(registerNodes)
