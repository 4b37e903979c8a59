// Paths and fixtures shared by the test suites.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/image.hpp"
#include "geobrush/registry.hpp"

namespace geobrush::test {

// ../shared/data/meshes beside the repository.
std::filesystem::path meshDir();
std::filesystem::path meshPath(const std::string& name);
std::filesystem::path sourceDir();
// The build's plugin directory (every node of the repository).
std::filesystem::path pluginDir();
// The plugins built only for loader tests (other ABI, throwing, broken...).
std::filesystem::path testPluginDir();
// The geobrush command-line program.
std::filesystem::path cliPath();

// A registry with every plugin of the build loaded (once per process).
const NodeRegistry& registry();
// What the loader refused while building registry(); empty in a good build.
const std::vector<std::string>& registryLoadErrors();

// A registry with only the test plugins loaded: test.number, test.add,
// test.fail, ... (tests/test_plugins/), and the refusals of the bad ones.
const NodeRegistry& testNodeRegistry();

// "'path'", as error messages quote file names.
std::string quoted(const std::filesystem::path& path);
// Passes when `text` contains `part`, and shows both when it does not.
::testing::AssertionResult contains(const std::string& text, const std::string& part);

// A fresh, empty folder under the system temp dir, removed at exit.
std::filesystem::path tempDir(const std::string& name);
// Writes `bytes` to `path` as they are; returns `path`.
std::filesystem::path writeFile(const std::filesystem::path& path, const std::string& bytes);

// The graph's node "metrics" and what it reads, run into a temp folder: the metrics' values
// (empty, and a failed expectation, when the run fails).
std::map<std::string, double> graphMetrics(Graph graph);
// The same of a graph file, with its parameters set by `assignments` (NODE.PARAM=VALUE, as
// `geobrush run --set` does).
std::map<std::string, double> graphMetrics(const std::filesystem::path& file,
                                           const std::vector<std::string>& assignments = {});

// The graph files of graphs/ (file names, sorted).
std::vector<std::string> shippedGraphs();
// Evaluates a graph file with every plugin, writing its outputs into `outDir`.
EvalReport runGraphFile(const std::filesystem::path& file, const std::filesystem::path& outDir);
// Whether an RGBA pixel is the renders' white background.
bool isBackground(const std::uint8_t* rgba);
// The share of an image's pixels that are not the white background.
double coverage(const Image& image);

}  // namespace geobrush::test
