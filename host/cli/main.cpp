// The `geobrush` command line: parsing only; the work is in commands.cpp.
#include <CLI/CLI.hpp>

#include "commands.hpp"
#include "geobrush/memory.hpp"

using namespace geobrush;

int main(int argc, char** argv) {
  geobrush::reuseFreedMemory();
  CLI::App app{"GeoBrush: clone 3D surface geometry with node graphs, headless."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "geobrush 0.1.0");

  cli::RunOptions run;
  auto* runCmd = app.add_subcommand("run", "Evaluate a graph file and write its outputs.");
  runCmd->add_option("graph", run.graph, "Graph file (.json)")->required();
  runCmd->add_option("--set", run.sets, "Override a parameter: NODE.PARAM=VALUE (repeatable)");
  runCmd->add_option("--out", run.outDir, "Folder for output files (default: the graph's folder)");
  runCmd->add_flag("--json", run.json, "Print a machine-readable report on stdout");
  runCmd->add_flag("--quiet", run.quiet, "Print nothing but errors");

  cli::CompareOptions compare;
  auto* compareCmd = app.add_subcommand(
      "compare", "Evaluate two graphs and set their metrics, node times and meshes side by side.");
  compareCmd->add_option("graph_a", compare.graphA, "First graph file (.json)")->required();
  compareCmd->add_option("graph_b", compare.graphB, "Second graph file (.json)")->required();
  compareCmd->add_option("--set", compare.sets,
                         "Override a parameter in both graphs: NODE.PARAM=VALUE (repeatable)");
  compareCmd->add_option("--out", compare.outDir,
                         "Folder for both graphs' outputs and the picture (default: .)");
  compareCmd->add_option("--image", compare.image, "PNG of both meshes (default: OUT/compare.png)");
  compareCmd->add_flag("--json", compare.json, "Print a machine-readable report on stdout");
  compareCmd->add_flag("--quiet", compare.quiet, "Print nothing but errors");

  std::filesystem::path validatePath;
  bool validateQuiet = false;
  auto* validateCmd = app.add_subcommand("validate", "Check a graph file without evaluating it.");
  validateCmd->add_option("graph", validatePath, "Graph file (.json)")->required();
  validateCmd->add_flag("--quiet", validateQuiet, "Print nothing but errors");

  bool nodesJson = false;
  auto* nodesCmd = app.add_subcommand("nodes", "List the node types of the loaded plugins.");
  nodesCmd->add_flag("--json", nodesJson, "Print as JSON");

  cli::RenderCommandOptions render;
  std::string backend = "auto";
  auto* renderCmd = app.add_subcommand("render", "Render mesh files to a PNG image.");
  renderCmd->add_option("meshes", render.meshes, "Mesh files (OBJ, PLY, OFF, STL)")->required();
  renderCmd->add_option("-o,--output", render.output, "PNG file to write")->required();
  renderCmd->add_option("--width", render.render.width, "Image width in pixels")
      ->check(CLI::Range(1, 8192));
  renderCmd->add_option("--height", render.render.height, "Image height in pixels")
      ->check(CLI::Range(1, 8192));
  renderCmd->add_option("--azimuth", render.render.view.azimuthDeg, "Degrees around +y");
  renderCmd->add_option("--elevation", render.render.view.elevationDeg, "Degrees above xz")
      ->check(CLI::Range(-89.0, 89.0));
  renderCmd->add_option("--fov", render.render.view.fovDeg, "Vertical field of view, degrees")
      ->check(CLI::Range(1.0, 170.0));
  renderCmd->add_option("--zoom", render.render.view.zoom, "Closer than the fitted view if > 1")
      ->check(CLI::PositiveNumber);
  renderCmd->add_flag("--wireframe", render.wireframe, "Draw triangle edges");
  renderCmd->add_option("--backend", backend, "auto, vulkan or cpu")
      ->check(CLI::IsMember({"auto", "vulkan", "cpu"}));

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? cli::kExitOk : cli::kExitUsage;
  }

  try {
    if (*runCmd) return cli::runGraph(run);
    if (*compareCmd) return cli::compareGraphs(compare);
    if (*validateCmd) return cli::validateGraph(validatePath, validateQuiet);
    if (*nodesCmd) return cli::listNodes(nodesJson);
    if (*renderCmd) {
      render.render.backend = backend == "vulkan" ? RenderBackend::Vulkan
                              : backend == "cpu"  ? RenderBackend::Cpu
                                                  : RenderBackend::Auto;
      return cli::renderFiles(render);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return cli::kExitEvaluation;
  }
  return cli::kExitUsage;
}
