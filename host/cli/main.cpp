// The `geobrush` command line: parsing only; the work is in commands.cpp.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cctype>

#include "commands.hpp"
#include "geobrush/memory.hpp"
#include "geobrush/text.hpp"

using namespace geobrush;

namespace {

// Accepts what a param of `decl` reads from its text form; the error is the param's.
CLI::Validator paramValidator(ParamDecl decl, const std::string& description) {
  return CLI::Validator(
      [decl](std::string& text) -> std::string {
        try {
          parseParamText(decl, text);
          return {};
        } catch (const std::invalid_argument& e) {
          return e.what();
        }
      },
      description);
}

ParamDecl numberDecl(ParamKind kind, std::optional<double> min, std::optional<double> max) {
  ParamDecl decl;
  decl.kind = kind;
  decl.defaultValue = kind == ParamKind::Int ? ParamValue(std::int64_t(0)) : ParamValue(0.0);
  decl.min = min;
  decl.max = max;
  return decl;
}

// Checks an option's text as the geobrush.render param of the same meaning reads it (the same
// parser and the range both take from render.hpp), so that the command and the node agree.
CLI::Validator renderRange(ParamKind kind, RenderRange range) {
  return paramValidator(numberDecl(kind, range.min, range.max),
                        "[" + formatParam(range.min) + ", " + formatParam(range.max) + "]");
}

// The image is always PNG: another extension would name a file in a format it is not.
CLI::Validator pngName() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        std::string extension = std::filesystem::path(text).extension().string();
        std::transform(extension.begin(), extension.end(), extension.begin(),
                       [](unsigned char c) { return char(std::tolower(c)); });
        if (extension == ".png") return {};
        return quoteText(text) + ": the image is written as PNG; name it .png";
      },
      "PNG");
}

ParamDecl pointDecl() {
  ParamDecl decl;
  decl.kind = ParamKind::Vec3;
  decl.defaultValue = Vec3{};
  return decl;
}

// A point "X,Y,Z" as a vec3 param reads it; the error names the option.
CLI::Validator point() {
  return paramValidator(pointDecl(), "X,Y,Z");
}

Vec3 pointOf(const std::string& text) {
  return std::get<Vec3>(parseParamText(pointDecl(), text));
}

// A number as a double param with these bounds reads it.
CLI::Validator numberIn(std::optional<double> min, std::optional<double> max) {
  return paramValidator(numberDecl(ParamKind::Double, min, max), "NUMBER");
}

// CLI11's errors as the program's other errors: one escaped, bounded "error:" line.
std::string failureLine(const CLI::App*, const CLI::Error& e) {
  return "error: " + messageLine(e.what()) + "\n";
}

}  // namespace

int main(int argc, char** argv) {
  geobrush::reuseFreedMemory();
  CLI::App app{"GeoBrush: clone 3D surface geometry with node graphs, headless."};
  app.require_subcommand(1);
  app.set_version_flag("--version", "geobrush 0.1.0");
  app.failure_message(failureLine);

  constexpr const char* kProgressHelp =
      "Print each node's progress as plain lines on stderr (on a terminal: one status line)";
  cli::RunOptions run;
  auto* runCmd = app.add_subcommand("run", "Evaluate a graph file and write its outputs.");
  runCmd->add_option("graph", run.graph, "Graph file (.json)")->required();
  runCmd->add_option("--set", run.sets, "Override a parameter: NODE.PARAM=VALUE (repeatable)");
  runCmd->add_option("--out", run.outDir, "Folder for output files (default: the graph's folder)");
  runCmd->add_flag("--json", run.json, "Print a machine-readable report on stdout");
  runCmd->add_flag("--quiet", run.quiet, "Print nothing but errors");
  runCmd->add_flag("--progress", run.progress, kProgressHelp);

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
  compareCmd->add_flag("--progress", compare.progress, kProgressHelp);

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
  renderCmd->add_option("-o,--output", render.output, "PNG file to write")
      ->required()
      ->check(pngName());
  renderCmd->add_option("--width", render.render.width, "Image width in pixels")
      ->check(renderRange(ParamKind::Int, kRenderSizeRange));
  renderCmd->add_option("--height", render.render.height, "Image height in pixels")
      ->check(renderRange(ParamKind::Int, kRenderSizeRange));
  renderCmd->add_option("--azimuth", render.render.view.azimuthDeg, "Degrees around +y")
      ->check(renderRange(ParamKind::Double, kRenderAzimuthRange));
  renderCmd->add_option("--elevation", render.render.view.elevationDeg, "Degrees above xz")
      ->check(renderRange(ParamKind::Double, kRenderElevationRange));
  renderCmd->add_option("--fov", render.render.view.fovDeg, "Vertical field of view, degrees")
      ->check(renderRange(ParamKind::Double, kRenderFovRange));
  renderCmd->add_option("--zoom", render.render.view.zoom, "Closer than the fitted view if > 1")
      ->check(renderRange(ParamKind::Double, kRenderZoomRange));
  std::string focus;
  double focusRadius = 0;
  renderCmd->add_option("--focus", focus, "X,Y,Z: the centre of the region to frame")
      ->check(point());
  renderCmd
      ->add_option("--focus-radius", focusRadius,
                   "Frame the ball of this radius around --focus (0: everything)")
      ->check(numberIn(0.0, kRenderFocusRadiusMax));
  renderCmd->add_flag("--wireframe", render.wireframe, "Draw triangle edges");
  renderCmd->add_option("--backend", backend, "auto, vulkan or cpu")
      ->check(CLI::IsMember({"auto", "vulkan", "cpu"}));

  cli::CloneOptions clone;
  bool listMethods = false;
  auto* cloneCmd = app.add_subcommand(
      "clone", "Clone the surface around a point of one mesh onto a point of another.");
  cloneCmd->add_flag("--list-methods", listMethods, "List the clone methods and exit");
  cloneCmd->add_option("--source", clone.request.spec.source, "The mesh the detail comes from");
  cloneCmd->add_option("--target", clone.request.spec.target, "The mesh it is pasted onto");
  std::string sourcePoint, targetPoint;
  cloneCmd
      ->add_option("--source-point", sourcePoint,
                   "X,Y,Z: the region's centre (snapped to the source surface)")
      ->check(point());
  cloneCmd
      ->add_option("--target-point", targetPoint,
                   "X,Y,Z: where the centre lands (snapped to the target surface)")
      ->check(point());
  cloneCmd
      ->add_option("--radius", clone.request.spec.radius,
                   "Geodesic radius of the region, in source mesh units")
      ->check(numberIn(0.0, std::nullopt));
  cloneCmd
      ->add_option("--scale", clone.request.spec.scale, "Target size over source size (default 1)")
      ->check(numberIn(0.0, std::nullopt));
  cloneCmd
      ->add_option("--angle", clone.request.spec.angleDeg, "Degrees the detail turns (default 0)")
      ->check(numberIn(-360.0, 360.0));
  cloneCmd->add_option("--method", clone.request.method, "The method's name (default geobrush)");
  cloneCmd->add_option("--set", clone.request.sets,
                       "Override a parameter of the filled method: NODE.PARAM=VALUE (repeatable)");
  cloneCmd->add_option("-o,--output", clone.request.outputs.mesh,
                       "The result mesh (default: SOURCE_on_TARGET.obj here)");
  cloneCmd->add_option("--image", clone.request.outputs.image, "A picture of the result (PNG)")
      ->check(pngName());
  cloneCmd->add_option("--save-graph", clone.saveGraph,
                       "Write the filled-in graph, which `geobrush run` and the studio open");
  cloneCmd->add_flag("--json", clone.json, "Print a machine-readable report on stdout");
  cloneCmd->add_flag("--quiet", clone.quiet, "Print nothing but errors");
  cloneCmd->add_flag("--progress", clone.progress, kProgressHelp);

  cli::FillOptions fill;
  auto* fillCmd = app.add_subcommand(
      "fill",
      "Fill a mesh's holes: each boundary loop chosen gets a patch like the surface around it.");
  fillCmd->add_option("mesh", fill.mesh, "The mesh with holes")->required();
  fillCmd->add_option("-o,--output", fill.output, "The filled mesh")->required();
  fillCmd->add_option("--holes", fill.holes,
                      "all (default), all-but-largest (keeps a bust's base or a sheet's edge open) "
                      "or loop ids like 0,2 (loops numbered by their smallest vertex index)");
  fillCmd->add_option("--max-border", fill.maxBorder, "Leave loops with more border edges open")
      ->check(CLI::Range(0, 100000000));
  fillCmd
      ->add_option("--continuity", fill.continuity,
                   "0: harmonic; 1: biharmonic, with slopes (default)")
      ->check(CLI::Range(0, 1));
  fillCmd->add_option("--image", fill.image, "A picture of the result (PNG)")->check(pngName());
  fillCmd->add_flag("--json", fill.json, "Print a machine-readable report on stdout");
  fillCmd->add_flag("--quiet", fill.quiet, "Print nothing but errors");
  fillCmd->add_flag("--progress", fill.progress, kProgressHelp);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int status = app.exit(e);
    return status == 0 ? cli::kExitOk : cli::kExitUsage;
  }

  try {
    if (*runCmd) return cli::runGraph(run);
    if (*cloneCmd && listMethods) return cli::listMethods();
    if (*cloneCmd) {
      for (const char* option :
           {"--source", "--source-point", "--radius", "--target", "--target-point"}) {
        if (cloneCmd->count(option) > 0) continue;
        cli::printError(std::string("clone: ") + option + " is required");
        return cli::kExitUsage;
      }
      clone.request.spec.sourcePoint = pointOf(sourcePoint);
      clone.request.spec.targetPoint = pointOf(targetPoint);
      return cli::cloneMeshes(clone);
    }
    if (*compareCmd) return cli::compareGraphs(compare);
    if (*fillCmd) return cli::fillHoles(fill);
    if (*validateCmd) return cli::validateGraph(validatePath, validateQuiet);
    if (*nodesCmd) return cli::listNodes(nodesJson);
    if (*renderCmd) {
      render.render.backend = backend == "vulkan" ? RenderBackend::Vulkan
                              : backend == "cpu"  ? RenderBackend::Cpu
                                                  : RenderBackend::Auto;
      if (focusRadius > 0) {
        if (focus.empty()) {
          cli::printError("render: --focus-radius needs --focus X,Y,Z");
          return cli::kExitUsage;
        }
        render.render.frame = RenderFrame{pointOf(focus), focusRadius};
      }
      return cli::renderFiles(render);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", messageLine(e.what()).c_str());
    return cli::kExitEvaluation;
  }
  return cli::kExitUsage;
}
