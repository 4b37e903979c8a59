// One suite every node type of the build must pass: documented ports and
// params, defaults that survive a graph-file round trip, cache keys that
// follow every param, no recomputation for an unrelated change, and no crash
// when computing with defaults.
#include <gtest/gtest.h>

#include <set>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "perturbed.hpp"
#include "test_support.hpp"
#include "wired_node.hpp"

using namespace geobrush;

namespace {

class Conformance : public testing::TestWithParam<std::string> {
 protected:
  const NodeType& type() const { return *test::registry().find(GetParam()); }

  std::optional<Graph> wired() const { return test::wiredNode(type(), "conformance"); }
};

}  // namespace

TEST(ConformanceSetup, EveryNodeFolderLoadsAsItsOwnPlugin) {
  EXPECT_TRUE(test::registryLoadErrors().empty()) << test::registryLoadErrors().front();
  std::set<std::string> libraries;
  for (const NodeType* type : test::registry().types()) {
    EXPECT_EQ(std::filesystem::path(type->library).filename(), expectedPluginFile(type->id));
    libraries.insert(type->library);
  }
  EXPECT_EQ(libraries.size(), test::registry().types().size());
  for (const char* id : {"geobrush.load_mesh", "geobrush.save_mesh", "geobrush.primitive",
                         "geobrush.transform", "geobrush.render"})
    EXPECT_NE(test::registry().find(id), nullptr) << id;
}

TEST_P(Conformance, IsDocumented) {
  EXPECT_FALSE(type().doc.empty());
  EXPECT_FALSE(type().label.empty()) << "give the type a label for the studio palette";
  EXPECT_FALSE(type().category.empty());
  EXPECT_GE(type().inputs.size() + type().outputs.size(), 1u);
  for (const auto& port : type().inputs)
    EXPECT_FALSE(port.doc.empty()) << port.name;
  for (const auto& port : type().outputs)
    EXPECT_FALSE(port.doc.empty()) << port.name;
  for (const auto& param : type().params) {
    EXPECT_FALSE(param.doc.empty()) << param.name;
    if (param.kind == ParamKind::Int || param.kind == ParamKind::Double) {
      EXPECT_TRUE(param.min && param.max) << param.name << ": numbers need a range";
    }
  }
  EXPECT_NE(type().create(), nullptr);
}

TEST_P(Conformance, ParamsSurviveAGraphFileRoundTrip) {
  for (bool useDefaults : {true, false}) {
    Graph graph;
    graph.nodes["subject"] = {type().id, type().version, {}};
    for (const auto& param : type().params)
      graph.nodes["subject"].params[param.name] =
          useDefaults ? param.defaultValue : test::perturbed(param);
    const std::string text = serializeGraph(graph, &test::registry());
    Graph read = parseGraph(text, "roundtrip.json");
    prepareGraph(read, test::registry(), /*requireInputs=*/false);
    for (const auto& param : type().params) {
      auto it = read.nodes["subject"].params.find(param.name);
      const ParamValue& value =
          it == read.nodes["subject"].params.end() ? param.defaultValue : it->second;
      EXPECT_EQ(value, graph.nodes["subject"].params[param.name]) << param.name << "\n" << text;
    }
    if (useDefaults) {
      EXPECT_EQ(text.find("\"params\""), std::string::npos) << text;
    }
    EXPECT_EQ(serializeGraph(read, &test::registry()), text);
  }
}

TEST_P(Conformance, EveryParamChangesTheCacheKey) {
  Graph graph;
  graph.nodes["subject"] = {type().id, type().version, {}};
  Evaluator evaluator(test::registry());
  const Hash base = evaluator.nodeKeys(graph).at("subject");
  for (const auto& param : type().params) {
    Graph changed = graph;
    changed.nodes["subject"].params[param.name] = test::perturbed(param);
    ASSERT_NE(changed.nodes["subject"].params[param.name], param.defaultValue) << param.name;
    EXPECT_NE(evaluator.nodeKeys(changed).at("subject"), base) << param.name;
  }
}

TEST_P(Conformance, UnrelatedChangeRecomputesNothingElse) {
  auto graph = wired();
  if (!graph) GTEST_SKIP() << "no node type produces one of the inputs";
  // "0unrelated" sorts first, so it runs before anything that may fail.
  graph->nodes["0unrelated"] = {"geobrush.primitive", 1, {}};
  prepareGraph(*graph, test::registry());
  EvalOptions options;
  options.outputDir = graph->baseDir();
  Evaluator evaluator(test::registry());
  const EvalReport first = evaluator.evaluate(*graph, options);
  if (!first.ok) {
    EXPECT_NE(first.error.find("node '"), std::string::npos) << first.error;
  }

  setParamFromText(*graph, test::registry(), "0unrelated.resolution=3");
  const auto before = evaluator.computeCount();
  const EvalReport second = evaluator.evaluate(*graph, options);
  EXPECT_EQ(evaluator.computeCount() - before, 1u);
  EXPECT_EQ(second.ok, first.ok);
  for (const auto& run : second.runs)
    if (run.node != "0unrelated") {
      EXPECT_TRUE(run.cacheHit) << run.node;
    }
}

TEST_P(Conformance, DefaultsComputeDeterministicallyOrFailWithAMessage) {
  auto graph = wired();
  if (!graph) GTEST_SKIP() << "no node type produces one of the inputs";
  prepareGraph(*graph, test::registry());
  EvalOptions options;
  options.outputDir = graph->baseDir();
  Evaluator first(test::registry());
  Evaluator second(test::registry());
  const EvalReport a = first.evaluate(*graph, options);
  const EvalReport b = second.evaluate(*graph, options);
  ASSERT_EQ(a.ok, b.ok);
  if (!a.ok) {
    // With defaults a feeder may fail too (nothing painted yet): the message
    // must still name the node that failed.
    EXPECT_EQ(a.error, b.error);
    EXPECT_NE(a.error.find(": node '"), std::string::npos) << a.error;
    return;
  }
  for (const auto& port : type().outputs) {
    auto x = first.output("subject", port.name);
    auto y = second.output("subject", port.name);
    ASSERT_TRUE(x && y) << port.name;
    EXPECT_EQ(x->typeId(), port.typeId);
    EXPECT_EQ(x->contentHash(), y->contentHash()) << port.name;
  }
}

// Inputs that do not belong together (each made from another mesh, as when a graph is wired
// across two clones) are refused with a message naming the node, or used: never read out of
// bounds (the sanitizer build runs this too) and never a crash.
TEST_P(Conformance, InputsFromDifferentMeshesAreRefusedOrUsedNeverReadOutOfBounds) {
  auto graph = test::wiredNode(type(), "conformance-mixed", /*mixedMeshes=*/true);
  if (!graph) GTEST_SKIP() << "no node type produces one of the inputs";
  prepareGraph(*graph, test::registry());
  EvalOptions options;
  options.outputDir = graph->baseDir();
  Evaluator evaluator(test::registry());
  const EvalReport report = evaluator.evaluate(*graph, options);
  if (!report.ok) {
    EXPECT_NE(report.error.find(": node '"), std::string::npos) << report.error;
  }
}

INSTANTIATE_TEST_SUITE_P(AllNodeTypes, Conformance, testing::ValuesIn(test::allNodeTypeIds()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return test::typeTestName(info.param);
                         });
