// Nodes hold no state that changes their results: an evaluator taken through a history of edits
// (strokes, target drags, every param of every node changed and restored) gives, after each
// edit, the outputs that a fresh evaluator gives on the same graph, bit for bit. Every clone
// method as a whole, and every node type on its own.
#include <gtest/gtest.h>

#include <limits>

#include "geobrush/clone.hpp"
#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "perturbed.hpp"
#include "test_support.hpp"
#include "wired_node.hpp"

using namespace geobrush;

namespace {

// A clone method's template on small procedural meshes: a relief plane as the source and a
// sphere as the target, as the live-brush benchmark wires them, at a test's size.
Graph smallClone(const std::string& method) {
  Graph graph = readMethod(method, defaultMethodDirs(), test::registry());
  graph.file = test::tempDir("history-" + method) / "graph.json";
  graph.nodes["source_mesh"] = GraphNode{"geobrush.primitive",
                                         1,
                                         {{"shape", std::string("plane")},
                                          {"size", 2.0},
                                          {"resolution", std::int64_t(32)},
                                          {"relief", 0.02}}};
  graph.nodes["target_mesh"] =
      GraphNode{"geobrush.primitive",
                1,
                {{"shape", std::string("sphere")}, {"resolution", std::int64_t(12)}}};
  graph.nodes.at("source_canvas").params = {{"origin", Vec3{0, 0, 0}},
                                            {"dabs", std::vector<double>{0, 0, 0, 0.45}}};
  graph.nodes.at("strokes").params = {{"dabs", std::vector<double>{0, 0, 0.15, 1}}};
  graph.nodes.at("target_map").params = {{"origin", Vec3{0, 0, 1}}};
  // A grid in proportion to these meshes (the default suits canvases of tens of thousands of
  // vertices): the history evaluates the graph hundreds of times.
  if (const auto roi = graph.nodes.find("roi"); roi != graph.nodes.end())
    roi->second.params[roi->second.type == "geobrush.texture_roi" ? "texture_size" : "resolution"] =
        std::int64_t(64);
  // Small images: a history writes hundreds.
  for (auto& [name, node] : graph.nodes)
    if (node.type == "geobrush.render") {
      node.params["width"] = std::int64_t(96);
      node.params["height"] = std::int64_t(72);
    }
  prepareGraph(graph, test::registry());
  return graph;
}

// One edit of the history: a name for messages and the change it makes.
struct Edit {
  std::string name;
  std::function<void(Graph&)> apply;
};

std::function<void(Graph&)> setParam(std::string node, std::string param, ParamValue value) {
  return [=](Graph& graph) { graph.nodes.at(node).params[param] = value; };
}

// Every param of every node changed on its own, then back (paths stay: they name files). A
// node's inputs change with the params of the nodes upstream of it.
std::vector<Edit> paramEdits(const Graph& start) {
  std::vector<Edit> edits;
  for (const auto& [name, node] : start.nodes) {
    const NodeType& type = *test::registry().find(node.type);
    for (const ParamDecl& decl : type.params) {
      if (decl.kind == ParamKind::InputPath || decl.kind == ParamKind::OutputPath) continue;
      auto it = node.params.find(decl.name);
      const ParamValue before = it == node.params.end() ? decl.defaultValue : it->second;
      ParamValue changed = test::perturbed(decl);
      if (changed == before) changed = decl.defaultValue;
      if (changed == before) continue;
      edits.push_back({name + "." + decl.name + " changed", setParam(name, decl.name, changed)});
      edits.push_back({name + "." + decl.name + " restored", setParam(name, decl.name, before)});
    }
  }
  return edits;
}

// A painting session: a stroke, a drag of the target and back, then every param.
std::vector<Edit> sessionEdits(const Graph& start) {
  std::vector<Edit> edits = {
      {"a second dab",
       setParam("strokes", "dabs", std::vector<double>{0, 0, 0.15, 1, 0.08, 0.02, 0.15, 1})},
      {"the target dragged", setParam("target_map", "origin", Vec3{0.04, 0.01, 1})},
      {"the target dragged on", setParam("target_map", "origin", Vec3{0.08, 0.03, 1})},
      {"the target dragged back", setParam("target_map", "origin", Vec3{0, 0, 1})}};
  for (Edit& edit : paramEdits(start))
    edits.push_back(std::move(edit));
  return edits;
}

// What an evaluation left: whether it succeeded, its error, and the content hash of every output.
struct Results {
  bool ok = false;
  std::string error;
  std::map<std::string, Hash> outputs;  // "node.port"
};

Results resultsOf(const Graph& graph, const EvalReport& report, const Evaluator& evaluator) {
  Results results{report.ok, report.error, {}};
  for (const auto& [name, node] : graph.nodes)
    for (const PortDecl& port : test::registry().find(node.type)->outputs)
      if (const ValuePtr value = evaluator.output(name, port.name))
        results.outputs[name + "." + port.name] = value->contentHash();
  return results;
}

void expectSame(const Results& kept, const Results& fresh, const std::string& after) {
  ASSERT_EQ(kept.ok, fresh.ok) << after << ": " << kept.error << " | " << fresh.error;
  EXPECT_EQ(kept.error, fresh.error) << after;
  for (const auto& [output, hash] : fresh.outputs) {
    const auto it = kept.outputs.find(output);
    ASSERT_NE(it, kept.outputs.end()) << after << ": " << output << " is missing";
    EXPECT_EQ(it->second, hash) << after << ": " << output << " differs from a fresh evaluator's";
  }
  EXPECT_EQ(kept.outputs.size(), fresh.outputs.size()) << after;
}

// Under the sanitizers the history evaluator takes every edit (its memory accesses are what they
// check) and a fresh evaluator checks its results after the first edits only: the comparison after
// every edit, one fresh evaluation of the whole graph each, is the optimized build's run of this
// suite.
#ifdef GEOBRUSH_UNDER_SANITIZERS
constexpr std::size_t kComparedEdits = 4;
#else
constexpr std::size_t kComparedEdits = std::numeric_limits<std::size_t>::max();
#endif

void runHistory(Graph graph, const std::vector<Edit>& edits) {
  EvalOptions options;
  options.outputDir = graph.baseDir();
  Evaluator history(test::registry());
  history.evaluate(graph, options);
  // A fresh evaluator's results per graph (a restored param gives the graph of an earlier step).
  std::map<std::string, Results> freshResults;
  for (std::size_t step = 0; step < edits.size(); ++step) {
    const Edit& edit = edits[step];
    edit.apply(graph);
    const EvalReport kept = history.evaluate(graph, options);
    EXPECT_FALSE(kept.historyDependent()) << "after " << edit.name;
    if (step >= kComparedEdits) continue;
    const std::string text = serializeGraph(graph, &test::registry());
    if (!freshResults.count(text)) {
      Evaluator fresh(test::registry());
      const EvalReport cold = fresh.evaluate(graph, options);
      freshResults[text] = resultsOf(graph, cold, fresh);
    }
    expectSame(resultsOf(graph, kept, history), freshResults.at(text), "after " + edit.name);
  }
}

class CloneHistory : public testing::TestWithParam<std::string> {};

}  // namespace

TEST_P(CloneHistory, EveryEditGivesWhatAFreshEvaluatorGives) {
  Graph graph = smallClone(GetParam());
  {
    Evaluator first(test::registry());
    EvalOptions options;
    options.outputDir = graph.baseDir();
    const EvalReport report = first.evaluate(graph, options);
    ASSERT_TRUE(report.ok) << report.error;
  }
  runHistory(graph, sessionEdits(graph));
}

// Every node type on its own, its inputs made by other types' nodes (wired_node.hpp: a relief
// plane, a canvas and a region painted on it): each of its params and each of its feeders'
// params (a change of its inputs) changed and restored. Where an input does not suit it, the
// node must fail alike every time.
class NodeHistory : public testing::TestWithParam<std::string> {};

TEST_P(NodeHistory, EveryEditGivesWhatAFreshEvaluatorGives) {
  const NodeType& type = *test::registry().find(GetParam());
  auto graph = test::wiredNode(type, "node-history");
  if (!graph) GTEST_SKIP() << "no node type produces one of the inputs";
  prepareGraph(*graph, test::registry());
  runHistory(*graph, paramEdits(*graph));
}

INSTANTIATE_TEST_SUITE_P(AllNodeTypes, NodeHistory, testing::ValuesIn(test::allNodeTypeIds()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           return test::typeTestName(info.param);
                         });

INSTANTIATE_TEST_SUITE_P(Methods, CloneHistory,
                         testing::Values("geobrush", "cutpaste", "variational", "emd", "additive",
                                         "dpm"));
