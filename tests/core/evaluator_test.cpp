// The evaluator: pull, cache keys, recomputation counts, failures, files.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <thread>

#include "geobrush/evaluator.hpp"
#include "geobrush/graph.hpp"
#include "geobrush/values.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

// a ─┐
//    ├─ sum ── fail ── write
// b ─┘
// c (independent)
Graph chain(const std::filesystem::path& file) {
  Graph graph = parseGraph(R"({
    "format": "geobrush-graph", "formatVersion": 1,
    "nodes": {
      "a": {"type": "test.number", "typeVersion": 1, "params": {"value": 2}},
      "b": {"type": "test.number", "typeVersion": 1, "params": {"value": 3}},
      "c": {"type": "test.number", "typeVersion": 1, "params": {"value": 9}},
      "sum": {"type": "test.add", "typeVersion": 2},
      "fail": {"type": "test.fail", "typeVersion": 1},
      "write": {"type": "test.write_text", "typeVersion": 1, "params": {"path": "out/sum.txt"}}
    },
    "connections": [{"from": "a.value", "to": "sum.a"}, {"from": "b.value", "to": "sum.b"},
                    {"from": "sum.value", "to": "fail.in"}, {"from": "fail.value", "to": "write.value"}]
  })",
                           file);
  prepareGraph(graph, test::testNodeRegistry());
  return graph;
}

double scalar(const Evaluator& evaluator, const std::string& node) {
  auto value = std::dynamic_pointer_cast<const Scalar>(evaluator.output(node, "value"));
  return value ? value->value : std::nan("");
}

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::string text;
  std::getline(in, text);
  return text;
}

}  // namespace

TEST(Evaluator, ComputesAndWritesFiles) {
  const auto dir = test::tempDir("eval-basic");
  std::filesystem::create_directories(dir / "out");
  Graph graph = chain(dir / "g.json");
  Evaluator evaluator(test::testNodeRegistry());
  EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_EQ(scalar(evaluator, "sum"), 5.0);
  EXPECT_EQ(report.computed(), 6);
  ASSERT_EQ(report.filesWritten.size(), 1u);
  EXPECT_EQ(report.filesWritten[0], dir / "out" / "sum.txt");
  EXPECT_EQ(readText(dir / "out" / "sum.txt"), "5");
}

TEST(Evaluator, SecondRunIsAllCacheHits) {
  const auto dir = test::tempDir("eval-cache");
  std::filesystem::create_directories(dir / "out");
  Graph graph = chain(dir / "g.json");
  Evaluator evaluator(test::testNodeRegistry());
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  const auto before = evaluator.computeCount();
  EvalReport again = evaluator.evaluate(graph);
  EXPECT_EQ(evaluator.computeCount(), before);
  EXPECT_EQ(again.cacheHits(), 6);
}

TEST(Evaluator, ChangingAParamRerunsOnlyDownstream) {
  const auto dir = test::tempDir("eval-downstream");
  std::filesystem::create_directories(dir / "out");
  Graph graph = chain(dir / "g.json");
  Evaluator evaluator(test::testNodeRegistry());
  ASSERT_TRUE(evaluator.evaluate(graph).ok);

  setParamFromText(graph, test::testNodeRegistry(), "b.value=10");
  EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  std::vector<std::string> recomputed;
  for (const auto& run : report.runs)
    if (!run.cacheHit) recomputed.push_back(run.node);
  EXPECT_EQ(recomputed, (std::vector<std::string>{"b", "sum", "fail", "write"}));
  EXPECT_EQ(scalar(evaluator, "sum"), 12.0);
  EXPECT_EQ(readText(dir / "out" / "sum.txt"), "12");

  // An unrelated node's param: nothing else recomputes.
  const auto before = evaluator.computeCount();
  setParamFromText(graph, test::testNodeRegistry(), "c.value=1");
  report = evaluator.evaluate(graph);
  EXPECT_EQ(evaluator.computeCount() - before, 1u);
  // A param that changes the key but not the value still recomputes only that node's chain.
  setParamFromText(graph, test::testNodeRegistry(), "c.label=renamed");
  EXPECT_EQ(evaluator.evaluate(graph).computed(), 1);
}

TEST(Evaluator, KeysDependOnTypeParamsAndInputsNotNames) {
  Graph graph = chain("/tmp/g.json");
  Evaluator evaluator(test::testNodeRegistry());
  auto keys = evaluator.nodeKeys(graph);
  Graph renamed = graph;
  renamed.nodes["z"] = renamed.nodes["c"];
  renamed.nodes.erase("c");
  EXPECT_EQ(evaluator.nodeKeys(renamed).at("z"), keys.at("c"));
  EXPECT_NE(keys.at("a"), keys.at("b"));
  setParamFromText(graph, test::testNodeRegistry(), "a.value=3");
  auto changed = evaluator.nodeKeys(graph);
  EXPECT_EQ(changed.at("a"), keys.at("b"));  // same type, same params
  EXPECT_NE(changed.at("sum"), keys.at("sum"));
  EXPECT_EQ(changed.at("c"), keys.at("c"));
  // Output paths resolve against the output folder, so --out changes the writer's key.
  EvalOptions elsewhere;
  elsewhere.outputDir = "/somewhere/else";
  EXPECT_NE(evaluator.nodeKeys(graph, elsewhere).at("write"), changed.at("write"));
  EXPECT_EQ(evaluator.nodeKeys(graph, elsewhere).at("sum"), changed.at("sum"));
}

TEST(Evaluator, TargetsPullOnlyUpstream) {
  Graph graph = chain(test::tempDir("eval-pull") / "g.json");
  Evaluator evaluator(test::testNodeRegistry());
  EvalOptions options;
  options.targets = {"sum"};
  EvalReport report = evaluator.evaluate(graph, options);
  ASSERT_TRUE(report.ok);
  EXPECT_EQ(report.runs.size(), 3u);
  EXPECT_TRUE(report.filesWritten.empty());
}

TEST(Evaluator, NodeFailuresAreReportedNotThrown) {
  const auto dir = test::tempDir("eval-fail");
  std::filesystem::create_directories(dir / "out");
  const std::pair<const char*, const char*> cases[] = {
      {"node_error", "node 'fail' param 'how': asked to fail"},
      {"std_exception", "node 'fail': failed: a std::exception from the node"},
      {"unknown", "node 'fail': failed with an unknown exception"},
      {"no_output", "node 'fail' output 'value': was not set by 'test.fail'"},
      {"wrong_type", "node 'fail' output 'value': was set to a geobrush.Metrics but is declared"},
  };
  for (const auto& [how, expected] : cases) {
    Graph graph = chain(dir / "g.json");
    setParamFromText(graph, test::testNodeRegistry(), std::string("fail.how=") + how);
    Evaluator evaluator(test::testNodeRegistry());
    EvalReport report = evaluator.evaluate(graph);
    EXPECT_FALSE(report.ok) << how;
    EXPECT_NE(report.error.find((dir / "g.json").string() + ": " + expected), std::string::npos)
        << report.error;
    EXPECT_TRUE(report.filesWritten.empty());
    EXPECT_FALSE(std::filesystem::exists(dir / "out" / "sum.txt")) << how;
    // A failure is remembered for its key: asking again does not recompute.
    const auto before = evaluator.computeCount();
    EXPECT_FALSE(evaluator.evaluate(graph).ok);
    EXPECT_EQ(evaluator.computeCount(), before);
  }
}

// Nodes whose inputs are ready together (independent branches) compute at the same time: two
// rendezvous nodes meet, which one at a time they never would. The report lists the runs in
// evaluation order, with the outputs a node at a time gives.
TEST(Evaluator, IndependentBranchesComputeAtTheSameTime) {
  Graph graph = parseGraph(R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"left": {"type": "test.rendezvous", "typeVersion": 1, "params": {"meeting": "branches"}},
              "right": {"type": "test.rendezvous", "typeVersion": 1, "params": {"meeting": "branches", "seat": 1}},
              "sum": {"type": "test.add", "typeVersion": 2}},
    "connections": [{"from": "left.value", "to": "sum.a"}, {"from": "right.value", "to": "sum.b"}]})",
                           "branches.json");
  prepareGraph(graph, test::testNodeRegistry());
  Evaluator evaluator(test::testNodeRegistry());
  std::vector<std::string> progressed;
  EvalOptions options;
  options.progress = [&](const std::string& node, double fraction) {
    if (fraction == 1.0) progressed.push_back(node);
  };
  const EvalReport report = evaluator.evaluate(graph, options);
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_EQ(scalar(evaluator, "sum"), 2.0);
  ASSERT_EQ(report.runs.size(), 3u);
  EXPECT_EQ(report.runs[0].node, "left");
  EXPECT_EQ(report.runs[1].node, "right");
  EXPECT_EQ(report.runs[2].node, "sum");
  // Each node's progress is reported from the evaluating thread, the one beside included.
  EXPECT_EQ(progressed, (std::vector<std::string>{"left", "right", "sum"}));
}

// A node failing beside an earlier one is reported only where a node at a time would reach it:
// the earlier node's failure wins, and after a success the run goes on until the failed node. A
// node that succeeded beside a failed earlier one leaves no output, as it would not have run.
TEST(Evaluator, AFailureBesideAnEarlierNodeIsReportedInOrder) {
  const auto graphWith = [](const std::string& firstHow, const std::string& secondHow) {
    const std::string text = R"({"format": "geobrush-graph", "formatVersion": 1,
      "nodes": {"n": {"type": "test.number", "typeVersion": 1},
                "a": {"type": "test.fail", "typeVersion": 1, "params": {"how": ")" +
                             firstHow + R"("}},
                "b": {"type": "test.fail", "typeVersion": 1, "params": {"how": ")" +
                             secondHow + R"("}},
                "c": {"type": "test.add", "typeVersion": 2}},
      "connections": [{"from": "n.value", "to": "a.in"}, {"from": "n.value", "to": "b.in"},
                      {"from": "a.value", "to": "c.a"}]})";
    Graph graph = parseGraph(text, "failing.json");
    prepareGraph(graph, test::testNodeRegistry());
    return graph;
  };
  for (const char* secondHow : {"node_error", "none"}) {
    Evaluator evaluator(test::testNodeRegistry());
    const EvalReport report = evaluator.evaluate(graphWith("std_exception", secondHow));
    EXPECT_FALSE(report.ok);
    EXPECT_EQ(report.errorNode, "a");
    ASSERT_EQ(report.runs.size(), 2u);
    EXPECT_EQ(report.runs.back().node, "a");
    EXPECT_EQ(evaluator.output("b", "value"), nullptr) << secondHow;
  }
  {
    // Order: n, a, b, c; b fails beside a, and the run stops at b with a's result kept.
    Evaluator evaluator(test::testNodeRegistry());
    const EvalReport report = evaluator.evaluate(graphWith("none", "node_error"));
    EXPECT_FALSE(report.ok);
    EXPECT_EQ(report.errorNode, "b");
    std::vector<std::string> runs;
    for (const auto& run : report.runs)
      runs.push_back(run.node);
    EXPECT_EQ(runs, (std::vector<std::string>{"n", "a", "b"}));
    EXPECT_TRUE(report.runs.back().failed);
    EXPECT_EQ(scalar(evaluator, "a"), 1.0);
  }
}

TEST(Evaluator, FailedRunLeavesNoFileAndOldFileIntact) {
  const auto dir = test::tempDir("eval-atomic");
  std::filesystem::create_directories(dir / "out");
  { std::ofstream(dir / "out" / "sum.txt") << "old\n"; }
  Graph graph = chain(dir / "g.json");
  // "write" runs (and writes its temporary file) before "zfail" fails.
  graph.nodes["zfail"] = {"test.fail", 1, {{"how", std::string("node_error")}}};
  graph.connections.push_back({{"sum", "value"}, {"zfail", "in"}});
  prepareGraph(graph, test::testNodeRegistry());
  Evaluator evaluator(test::testNodeRegistry());
  EvalReport report = evaluator.evaluate(graph);
  EXPECT_FALSE(report.ok);
  ASSERT_EQ(report.runs.back().node, "zfail");
  EXPECT_EQ(report.runs[report.runs.size() - 2].node, "write");
  EXPECT_EQ(readText(dir / "out" / "sum.txt"), "old");
  // No temporary file is left behind either.
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir / "out"), {}), 1);
}

TEST(Evaluator, MissingOutputFolderIsANodeError) {
  const auto dir = test::tempDir("eval-nofolder");
  Graph graph = chain(dir / "g.json");
  Evaluator evaluator(test::testNodeRegistry());
  EvalReport report = evaluator.evaluate(graph);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.error.find("node 'write': cannot write"), std::string::npos) << report.error;
  EXPECT_NE(report.error.find("does not exist"), std::string::npos) << report.error;
}

TEST(Evaluator, CancellationStopsALongNode) {
  Graph graph = parseGraph(R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"n": {"type": "test.number", "typeVersion": 1}, "s": {"type": "test.slow", "typeVersion": 1}},
    "connections": [{"from": "n.value", "to": "s.in"}]})",
                           "slow.json");
  prepareGraph(graph, test::testNodeRegistry());
  Evaluator evaluator(test::testNodeRegistry());
  std::atomic<bool> cancel{false};
  EvalOptions options;
  options.cancel = &cancel;
  double lastProgress = -1;
  options.progress = [&](const std::string& node, double fraction) {
    if (node == "s") lastProgress = fraction;
    if (node == "s" && fraction > 0.01) cancel = true;
  };
  EvalReport report = evaluator.evaluate(graph, options);
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(report.cancelled);
  EXPECT_LT(lastProgress, 0.5);
  // Cancelled work is not cached: it runs again when asked.
  cancel = false;
  options.progress = nullptr;
  EXPECT_TRUE(evaluator.evaluate(graph, options).ok);
}

TEST(Evaluator, InputFileChangesInvalidateTheKey) {
  const auto dir = test::tempDir("eval-inputfile");
  { std::ofstream(dir / "n.txt") << "1.5\n"; }
  Graph graph = parseGraph(R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"r": {"type": "test.read_text", "typeVersion": 1, "params": {"path": "n.txt"}}}})",
                           dir / "g.json");
  prepareGraph(graph, test::testNodeRegistry());
  Evaluator evaluator(test::testNodeRegistry());
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  EXPECT_EQ(scalar(evaluator, "r"), 1.5);
  EXPECT_EQ(evaluator.evaluate(graph).cacheHits(), 1);
  { std::ofstream(dir / "n.txt") << "-20.25\n"; }  // another size, so another key
  EvalReport report = evaluator.evaluate(graph);
  EXPECT_EQ(report.computed(), 1);
  EXPECT_EQ(scalar(evaluator, "r"), -20.25);
  std::filesystem::remove(dir / "n.txt");
  report = evaluator.evaluate(graph);
  EXPECT_FALSE(report.ok);
  EXPECT_NE(report.error.find("node 'r' param 'path': cannot read"), std::string::npos)
      << report.error;
}

TEST(Evaluator, DeterministicAcrossEvaluators) {
  const auto dir = test::tempDir("eval-determinism");
  std::filesystem::create_directories(dir / "out");
  Graph graph = chain(dir / "g.json");
  Evaluator first(test::testNodeRegistry());
  Evaluator second(test::testNodeRegistry());
  ASSERT_TRUE(first.evaluate(graph).ok);
  ASSERT_TRUE(second.evaluate(graph).ok);
  EXPECT_EQ(first.output("sum", "value")->contentHash(),
            second.output("sum", "value")->contentHash());
  EXPECT_EQ(first.nodeKeys(graph), second.nodeKeys(graph));
}

TEST(Evaluator, SettlingRecomputesWhatAWarmStartProducedWithFreshInstances) {
  const auto dir = test::tempDir("eval-settle");
  Graph graph = parseGraph(R"({
    "format": "geobrush-graph", "formatVersion": 1,
    "nodes": {
      "a": {"type": "test.number", "typeVersion": 1, "params": {"value": 2}},
      "warm": {"type": "test.warm", "typeVersion": 1},
      "sum": {"type": "test.add", "typeVersion": 2},
      "other": {"type": "test.add", "typeVersion": 2}
    },
    "connections": [{"from": "a.value", "to": "warm.in"}, {"from": "warm.value", "to": "sum.a"},
                    {"from": "a.value", "to": "other.a"}]
  })",
                           dir / "g.json");
  prepareGraph(graph, test::testNodeRegistry());
  Evaluator evaluator(test::testNodeRegistry());
  EvalReport first = evaluator.evaluate(graph);
  ASSERT_TRUE(first.ok) << first.error;
  EXPECT_FALSE(first.historyDependent());
  EXPECT_EQ(scalar(evaluator, "sum"), 2.0);

  // The second compute of the warm node starts from the first: off by its tolerance, and so is
  // everything downstream, but not a node beside it.
  graph.nodes.at("a").params["value"] = 3.0;
  EvalReport warm = evaluator.evaluate(graph);
  ASSERT_TRUE(warm.ok) << warm.error;
  EXPECT_TRUE(warm.historyDependent());
  std::map<std::string, bool> history;
  for (const auto& run : warm.runs)
    history[run.node] = run.history;
  EXPECT_TRUE(history.at("warm"));
  EXPECT_TRUE(history.at("sum"));
  EXPECT_FALSE(history.at("other"));
  EXPECT_FALSE(history.at("a"));
  EXPECT_NE(scalar(evaluator, "sum"), 3.0);

  // A plain evaluation keeps the warm result; settling recomputes the warm node and what it
  // feeds, cold, and nothing else.
  EXPECT_EQ(evaluator.evaluate(graph).computed(), 0);
  EvalOptions settle;
  settle.settle = true;
  EvalReport settled = evaluator.evaluate(graph, settle);
  ASSERT_TRUE(settled.ok) << settled.error;
  EXPECT_FALSE(settled.historyDependent());
  EXPECT_EQ(settled.computed(), 2);
  EXPECT_EQ(scalar(evaluator, "sum"), 3.0);
  Evaluator fresh(test::testNodeRegistry());
  ASSERT_TRUE(fresh.evaluate(graph).ok);
  EXPECT_EQ(scalar(fresh, "sum"), scalar(evaluator, "sum"));
  // Settled results are cached as such: settling again computes nothing.
  EXPECT_EQ(evaluator.evaluate(graph, settle).computed(), 0);
}

// x ─┬─ first  (derived_square)
//    └─ second (derived_square)
TEST(Evaluator, DerivedDataIsKeyedByTheInputsItNamesAndSharedAndDropped) {
  const auto dir = test::tempDir("eval-derived");
  Graph graph = parseGraph(R"({
    "format": "geobrush-graph", "formatVersion": 1,
    "nodes": {
      "x": {"type": "test.number", "typeVersion": 1, "params": {"value": 3}},
      "first": {"type": "test.derived_square", "typeVersion": 1},
      "second": {"type": "test.derived_square", "typeVersion": 1, "params": {"gain": 2}}
    },
    "connections": [{"from": "x.value", "to": "first.in"}, {"from": "x.value", "to": "second.in"}]
  })",
                           dir / "g.json");
  prepareGraph(graph, test::testNodeRegistry());
  Evaluator evaluator(test::testNodeRegistry());
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  EXPECT_EQ(scalar(evaluator, "first"), 3 + 9);
  EXPECT_EQ(scalar(evaluator, "second"), 6 + 9);
  EXPECT_EQ(evaluator.derivedBuildCount(), 1u);  // both nodes share it

  // A param the derivation does not name: the node computes again, the square stays.
  setParamFromText(graph, test::testNodeRegistry(), "first.gain=4");
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  EXPECT_EQ(scalar(evaluator, "first"), 12 + 9);
  EXPECT_EQ(evaluator.derivedBuildCount(), 1u);

  // A new input value: a new square; the old one goes once two evaluations have not used it.
  setParamFromText(graph, test::testNodeRegistry(), "x.value=5");
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  EXPECT_EQ(scalar(evaluator, "second"), 10 + 25);
  EXPECT_EQ(evaluator.derivedBuildCount(), 2u);
  EXPECT_EQ(evaluator.derivedHeld(), 2u);
  setParamFromText(graph, test::testNodeRegistry(), "first.gain=1");
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  EXPECT_EQ(evaluator.derivedHeld(), 1u);
  EXPECT_EQ(evaluator.derivedBuildCount(), 2u);
  evaluator.clearCache();
  EXPECT_EQ(evaluator.derivedHeld(), 0u);
}

namespace {

// a ─┬──────────── prep.a (read in prepare)
//    └─ wait ───── prep.b
Graph preparedSum(const std::filesystem::path& file, double value, const std::string& how,
                  const std::string& waitType = "test.await_prepared",
                  const std::string& waitParams = "") {
  std::string text = R"({
    "format": "geobrush-graph", "formatVersion": 1,
    "nodes": {
      "a": {"type": "test.number", "typeVersion": 1, "params": {"value": VALUE}},
      "wait": {"type": "WAIT", "typeVersion": 1, "params": PARAMS},
      "prep": {"type": "test.prepared_add", "typeVersion": 1, "params": {"how": "HOW"}}
    },
    "connections": [{"from": "a.value", "to": "prep.a"}, {"from": "a.value", "to": "wait.in"},
                    {"from": "wait.value", "to": "prep.b"}]
  })";
  auto replace = [&](const std::string& key, const std::string& with) {
    text.replace(text.find(key), key.size(), with);
  };
  const std::string number = std::to_string(value);
  replace("VALUE", number);
  replace("WAIT", waitType);
  replace("PARAMS", waitParams.empty() ? "{\"token\": " + number + "}" : waitParams);
  replace("HOW", how);
  Graph graph = parseGraph(text, file);
  prepareGraph(graph, test::testNodeRegistry());
  return graph;
}

const NodeRun& runOf(const EvalReport& report, const std::string& node) {
  for (const auto& run : report.runs)
    if (run.node == node) return run;
  throw std::out_of_range("no run of " + node);
}

}  // namespace

// prep's prepare() needs only a: it runs while wait computes, and wait sees it (else wait passes
// -1000 on after two seconds). The result is what a sequential evaluation gives.
TEST(Evaluator, PrepareRunsWhileTheNodesOtherInputsCompute) {
  const auto dir = test::tempDir("eval-prepare");
  Graph graph = preparedSum(dir / "g.json", 7, "none");
  Evaluator evaluator(test::testNodeRegistry());
  const EvalReport report = evaluator.evaluate(graph);
  ASSERT_TRUE(report.ok) << report.error;
  EXPECT_EQ(scalar(evaluator, "prep"), 14.0);
  EXPECT_EQ(runOf(report, "prep").warnings, std::vector<std::string>{"prepared from 7.000000"});
  EXPECT_EQ(evaluator.evaluate(graph).computed(), 0);
  // Its cached warnings stay; a changed input prepares and computes again.
  graph.nodes.at("a").params["value"] = 8.0;
  graph.nodes.at("wait").params["token"] = 8.0;
  const EvalReport again = evaluator.evaluate(graph);
  ASSERT_TRUE(again.ok) << again.error;
  EXPECT_EQ(scalar(evaluator, "prep"), 16.0);
}

TEST(Evaluator, APrepareThatThrowsFailsItsNode) {
  const auto dir = test::tempDir("eval-prepare-fails");
  Evaluator evaluator(test::testNodeRegistry());
  const EvalReport failed = evaluator.evaluate(
      preparedSum(dir / "g.json", 11, "fail_in_prepare", "test.fail", R"({"how": "none"})"));
  EXPECT_FALSE(failed.ok);
  EXPECT_TRUE(runOf(failed, "prep").failed);
  EXPECT_NE(failed.error.find("prep"), std::string::npos) << failed.error;
  EXPECT_NE(failed.error.find("refused while preparing"), std::string::npos) << failed.error;
  EXPECT_NE(failed.error.find("input 'a'"), std::string::npos) << failed.error;

  const EvalReport output = evaluator.evaluate(
      preparedSum(dir / "g2.json", 12, "output_in_prepare", "test.fail", R"({"how": "none"})"));
  EXPECT_FALSE(output.ok);
  EXPECT_NE(output.error.find("prepare()"), std::string::npos) << output.error;
}

// The other input fails while prepare() runs: the failure is that node's, and the evaluation
// waits for the preparation before it returns.
TEST(Evaluator, AnInputFailingWhileANodePreparesIsReported) {
  const auto dir = test::tempDir("eval-prepare-input-fails");
  Evaluator evaluator(test::testNodeRegistry());
  const EvalReport report = evaluator.evaluate(
      preparedSum(dir / "g.json", 13, "none", "test.fail", R"({"how": "node_error"})"));
  EXPECT_FALSE(report.ok);
  EXPECT_TRUE(runOf(report, "wait").failed);
  EXPECT_NE(report.error.find("asked to fail"), std::string::npos) << report.error;
  EXPECT_THROW(runOf(report, "prep"), std::out_of_range);
}

namespace {

// x ── scale (recycling_scale)
Graph recyclingScale(const std::filesystem::path& file) {
  Graph graph = parseGraph(R"({
    "format": "geobrush-graph", "formatVersion": 1,
    "nodes": {
      "x": {"type": "test.number", "typeVersion": 1, "params": {"value": 3}},
      "scale": {"type": "test.recycling_scale", "typeVersion": 1}
    },
    "connections": [{"from": "x.value", "to": "scale.in"}]
  })",
                           file);
  prepareGraph(graph, test::testNodeRegistry());
  return graph;
}

}  // namespace

// The evaluator keeps two runs' outputs; the one of two edits ago is retired as the next run
// starts and handed back to its node, unless something still holds it or the node refuses its
// note. The results are a fresh evaluator's either way.
TEST(Evaluator, RetiredOutputsGoBackToTheirNodeWhereNothingHoldsThem) {
  const auto dir = test::tempDir("eval-recycle");
  Graph graph = recyclingScale(dir / "g.json");
  Evaluator evaluator(test::testNodeRegistry());
  std::vector<const Value*> made;
  ValuePtr held;
  std::weak_ptr<const Value> fourth;
  for (int gain = 1; gain <= 8; ++gain) {
    SCOPED_TRACE(gain);
    if (gain == 6) setParamFromText(graph, test::testNodeRegistry(), "x.value=4");
    setParamFromText(graph, test::testNodeRegistry(), "scale.gain=" + std::to_string(gain));
    ASSERT_TRUE(evaluator.evaluate(graph).ok);
    const ValuePtr value = evaluator.output("scale", "value");
    made.push_back(value.get());
    if (gain == 2 || gain == 6) held = value;
    if (gain == 4) fourth = value;
    EXPECT_EQ(scalar(evaluator, "scale"), (gain >= 6 ? 4 : 3) * gain);
    Evaluator fresh(test::testNodeRegistry());
    ASSERT_TRUE(fresh.evaluate(graph).ok);
    EXPECT_EQ(scalar(fresh, "scale"), scalar(evaluator, "scale"));
  }
  EXPECT_EQ(made[2], made[0]);  // retired as the third run started, recycled in it
  EXPECT_NE(made[3], made[1]);  // held here
  EXPECT_EQ(made[4], made[2]);  // the third, recycled in the fifth run
  // The fourth, retired as the sixth run started, was made from another input than the sixth's:
  // the node refused it, and the bin let it go.
  EXPECT_TRUE(fourth.expired());
  // The sixth, retired as the eighth run started, is held here: the bin keeps it.
  EXPECT_NE(made[7], made[5]);
  EXPECT_EQ(evaluator.recycledHeld(), 1u);
  // A node taken out of the graph takes its retired values with it.
  graph.nodes.erase("scale");
  graph.connections.clear();
  ASSERT_TRUE(evaluator.evaluate(graph).ok);
  EXPECT_EQ(evaluator.recycledHeld(), 0u);
}
