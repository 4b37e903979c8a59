// Graph files: parsing, round trips, and every kind of bad file.
#include <gtest/gtest.h>

#include <fstream>

#include "geobrush/graph.hpp"
#include "test_support.hpp"

using namespace geobrush;

namespace {

const char* kSumGraph = R"({
  "format": "geobrush-graph", "formatVersion": 1,
  "nodes": {
    "a": {"type": "test.number", "typeVersion": 1, "params": {"value": 2}},
    "b": {"type": "test.number", "typeVersion": 1, "params": {"value": 3.5}},
    "sum": {"type": "test.add", "typeVersion": 2}
  },
  "connections": [{"from": "a.value", "to": "sum.a"}, {"from": "b.value", "to": "sum.b"}],
  "ui": {"a": {"x": 10, "y": -20}}
})";

std::string prepareError(const std::string& json) {
  try {
    Graph graph = parseGraph(json, "bad.json");
    prepareGraph(graph, test::testNodeRegistry());
  } catch (const GraphError& e) {
    return e.what();
  }
  return "no error";
}

std::string replaceOnce(std::string text, const std::string& from, const std::string& to) {
  auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

}  // namespace

TEST(GraphFile, ParsesNodesConnectionsAndUi) {
  Graph graph = parseGraph(kSumGraph, "/tmp/sum.json");
  ASSERT_EQ(graph.nodes.size(), 3u);
  EXPECT_EQ(graph.nodes.at("a").type, "test.number");
  EXPECT_EQ(std::get<std::int64_t>(graph.nodes.at("a").params.at("value")), 2);
  ASSERT_EQ(graph.connections.size(), 2u);
  EXPECT_EQ(graph.connections[1].to, (Endpoint{"sum", "b"}));
  EXPECT_EQ(graph.ui.at("a"), (UiPosition{10, -20}));
  EXPECT_EQ(graph.baseDir(), std::filesystem::path("/tmp"));
}

TEST(GraphFile, PrepareCoercesParamsToDeclaredKinds) {
  Graph graph = parseGraph(kSumGraph, "sum.json");
  prepareGraph(graph, test::testNodeRegistry());
  // "value": 2 was read as an integer; the param is declared as a double.
  EXPECT_EQ(std::get<double>(graph.nodes.at("a").params.at("value")), 2.0);
}

TEST(GraphFile, RoundTripIsByteStableAndDropsDefaults) {
  Graph graph = parseGraph(kSumGraph, "sum.json");
  prepareGraph(graph, test::testNodeRegistry());
  graph.nodes.at("sum").params["unused"] = std::int64_t(0);  // equal to the default
  const std::string once = serializeGraph(graph, &test::testNodeRegistry());
  EXPECT_EQ(once.find("unused"), std::string::npos) << once;
  Graph again = parseGraph(once, "sum.json");
  prepareGraph(again, test::testNodeRegistry());
  EXPECT_EQ(serializeGraph(again, &test::testNodeRegistry()), once);
  EXPECT_EQ(again.connections, graph.connections);
  EXPECT_EQ(again.ui, graph.ui);
}

TEST(GraphFile, WritesAtomically) {
  const auto dir = test::tempDir("graph-write");
  Graph graph = parseGraph(kSumGraph, dir / "g.json");
  writeGraphFile(graph, dir / "g.json");
  Graph read = readGraphFile(dir / "g.json");
  EXPECT_EQ(read.nodes.size(), 3u);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 1);
  EXPECT_THROW(writeGraphFile(graph, dir / "missing" / "g.json"), GraphError);
}

TEST(GraphFile, UpgradesOlderTypeVersions) {
  std::string json =
      replaceOnce(kSumGraph, R"("type": "test.add", "typeVersion": 2})",
                  R"("type": "test.add", "typeVersion": 1, "params": {"spare": 4}})");
  Graph graph = parseGraph(json, "old.json");
  prepareGraph(graph, test::testNodeRegistry());
  EXPECT_EQ(graph.nodes.at("sum").typeVersion, 2);
  EXPECT_EQ(std::get<std::int64_t>(graph.nodes.at("sum").params.at("unused")), 4);
  EXPECT_FALSE(graph.nodes.at("sum").params.count("spare"));
}

TEST(GraphFile, SetParamFromText) {
  Graph graph = parseGraph(kSumGraph, "sum.json");
  prepareGraph(graph, test::testNodeRegistry());
  setParamFromText(graph, test::testNodeRegistry(), "a.value=-7.25");
  EXPECT_EQ(std::get<double>(graph.nodes.at("a").params.at("value")), -7.25);
  EXPECT_THROW(setParamFromText(graph, test::testNodeRegistry(), "a.value=abc"), GraphError);
  EXPECT_THROW(setParamFromText(graph, test::testNodeRegistry(), "nobody.value=1"), GraphError);
  EXPECT_THROW(setParamFromText(graph, test::testNodeRegistry(), "a.nothing=1"), GraphError);
  EXPECT_THROW(setParamFromText(graph, test::testNodeRegistry(), "a.value=1e12"),
               GraphError);  // range
  EXPECT_THROW(setParamFromText(graph, test::testNodeRegistry(), "novalue"), GraphError);
}

TEST(GraphFile, TopologicalOrderIsDeterministic) {
  Graph graph = parseGraph(kSumGraph, "sum.json");
  EXPECT_EQ(topologicalOrder(graph), (std::vector<std::string>{"a", "b", "sum"}));
}

// Each bad file gives one line naming the file, the node and the port.
TEST(GraphFileErrors, MalformedJson) {
  auto error = prepareError(R"({"format": "geobrush-graph", "formatVersion": 1, "nodes": {)");
  EXPECT_NE(error.find("bad.json: malformed JSON: parse error at line 1"), std::string::npos)
      << error;
}

TEST(GraphFileErrors, WrongFormatOrNewerVersion) {
  EXPECT_NE(
      prepareError(replaceOnce(kSumGraph, "geobrush-graph", "other")).find("not a GeoBrush graph"),
      std::string::npos);
  auto newer =
      prepareError(replaceOnce(kSumGraph, R"("formatVersion": 1)", R"("formatVersion": 2)"));
  EXPECT_NE(newer.find("formatVersion 2 was written by a newer GeoBrush"), std::string::npos)
      << newer;
  auto missing = prepareError(replaceOnce(kSumGraph, R"("formatVersion": 1,)", ""));
  EXPECT_NE(missing.find("missing \"formatVersion\""), std::string::npos) << missing;
}

TEST(GraphFileErrors, UnknownNodeTypeNamesThePlugin) {
  auto error =
      prepareError(replaceOnce(kSumGraph, R"("type": "test.add")", R"("type": "acme.warp")"));
  EXPECT_NE(error.find("bad.json: node 'sum': unknown node type 'acme.warp'"), std::string::npos)
      << error;
  EXPECT_NE(error.find("expected plugin acme_warp.so"), std::string::npos) << error;
}

TEST(GraphFileErrors, RefusedPluginIsNamedForItsType) {
  auto error = prepareError(replaceOnce(kSumGraph, R"("type": "test.add", "typeVersion": 2)",
                                        R"("type": "test.other_abi", "typeVersion": 1)"));
  EXPECT_NE(error.find("node 'sum': node type 'test.other_abi' is unavailable"), std::string::npos)
      << error;
  EXPECT_NE(error.find("built for plugin ABI 999"), std::string::npos) << error;
}

TEST(GraphFileErrors, NewerTypeVersion) {
  auto error = prepareError(replaceOnce(kSumGraph, R"("typeVersion": 2)", R"("typeVersion": 5)"));
  EXPECT_NE(error.find("node 'sum': saved with typeVersion 5"), std::string::npos) << error;
}

TEST(GraphFileErrors, MissingNodeOrPort) {
  auto node = prepareError(replaceOnce(kSumGraph, R"("from": "b.value")", R"("from": "c.value")"));
  EXPECT_NE(node.find("node 'c' connection 'c.value -> sum.b': no node named 'c'"),
            std::string::npos)
      << node;
  auto out = prepareError(replaceOnce(kSumGraph, R"("from": "b.value")", R"("from": "b.mesh")"));
  EXPECT_NE(out.find("node 'b' output 'mesh': 'test.number' has no such output"), std::string::npos)
      << out;
  auto in = prepareError(replaceOnce(kSumGraph, R"("to": "sum.b")", R"("to": "sum.c")"));
  EXPECT_NE(in.find("node 'sum' input 'c'"), std::string::npos) << in;
}

TEST(GraphFileErrors, UnconnectedRequiredInput) {
  auto error = prepareError(replaceOnce(kSumGraph, R"({"from": "a.value", "to": "sum.a"}, )", ""));
  EXPECT_NE(error.find("node 'sum' input 'a': is not connected"), std::string::npos) << error;
  // While editing, open inputs are allowed.
  Graph editing = parseGraph(replaceOnce(kSumGraph, R"({"from": "a.value", "to": "sum.a"}, )", ""),
                             "editing.json");
  EXPECT_NO_THROW(prepareGraph(editing, test::testNodeRegistry(), false));
}

TEST(GraphFileErrors, TypeMismatch) {
  const char* json = R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"n": {"type": "test.number", "typeVersion": 1},
              "w": {"type": "test.write_text", "typeVersion": 1},
              "f": {"type": "test.fail", "typeVersion": 1, "params": {"how": "wrong_type"}}},
    "connections": [{"from": "n.value", "to": "f.in"}, {"from": "f.value", "to": "w.value"}]})";
  EXPECT_EQ(prepareError(json),
            "no error");  // declared types match; runtime types are checked later
  const char* mismatch = R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"n": {"type": "test.number", "typeVersion": 1},
              "m": {"type": "test.metric_count", "typeVersion": 1}},
    "connections": [{"from": "n.value", "to": "m.metrics"}]})";
  auto error = prepareError(mismatch);
  EXPECT_NE(error.find("bad.json: node 'm' input 'metrics': type mismatch: it takes "
                       "geobrush.Metrics but 'n.value' gives geobrush.Scalar"),
            std::string::npos)
      << error;
}

TEST(GraphFileErrors, Cycle) {
  const char* json = R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"x": {"type": "test.add", "typeVersion": 2}, "y": {"type": "test.add", "typeVersion": 2}},
    "connections": [{"from": "x.value", "to": "y.a"}, {"from": "y.value", "to": "x.a"}]})";
  auto error = prepareError(json);
  EXPECT_NE(error.find("the graph has a cycle: 'y' -> 'x' -> 'y'"), std::string::npos) << error;
}

TEST(GraphFileErrors, BadParams) {
  auto unknown = prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("valeu": 2})"));
  EXPECT_NE(
      unknown.find(
          "node 'a' param 'valeu': 'test.number' has no such parameter (it has: value, label)"),
      std::string::npos)
      << unknown;
  auto kind = prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": "two"})"));
  EXPECT_NE(kind.find("node 'a' param 'value': expected a number, got a string"), std::string::npos)
      << kind;
  auto range = prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": 2e10})"));
  EXPECT_NE(range.find("outside [-1e+09, 1e+09]"), std::string::npos) << range;
}

TEST(GraphFileErrors, DuplicateInputConnection) {
  auto error = prepareError(replaceOnce(kSumGraph, R"("to": "sum.b")", R"("to": "sum.a")"));
  EXPECT_NE(error.find("node 'sum' input 'a': has more than one incoming connection"),
            std::string::npos)
      << error;
}

TEST(GraphFileErrors, UnknownKeysAndMissingFile) {
  auto typo = prepareError(replaceOnce(kSumGraph, R"("connections")", R"("conections")"));
  EXPECT_NE(typo.find("unknown key \"conections\""), std::string::npos) << typo;
  try {
    readGraphFile("/nonexistent/graph.json");
    FAIL();
  } catch (const GraphError& e) {
    EXPECT_STREQ(e.what(), "/nonexistent/graph.json: no such file");
  }
}
