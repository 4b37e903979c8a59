// Graph files: parsing, round trips, and every kind of bad file.
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <fstream>
#include <sstream>
#include <thread>

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

// A file in the writer's own layout, its nodes, params and ui entries out of name order.
const char* kUnsortedGraph = R"({
  "format": "geobrush-graph",
  "formatVersion": 1,
  "nodes": {
    "zeta": {
      "type": "test.number",
      "typeVersion": 1,
      "params": {
        "value": 2.5,
        "label": "z",
        "list": [1.0, 2.0, 3.0],
        "dabs": [
          [0.5, 1.0, 1.5, 2.0],
          [3.0, 4.0, 5.0, 6.0]
        ]
      }
    },
    "alpha": {"type": "test.number", "typeVersion": 1},
    "mid": {"type": "test.add", "typeVersion": 2}
  },
  "connections": [
    {"from": "zeta.value", "to": "mid.a"},
    {"from": "alpha.value", "to": "mid.b"}
  ],
  "ui": {
    "mid": {"x": 1.5, "y": 2.0},
    "alpha": {"x": -3.0, "y": 4.0}
  }
}
)";

TEST(GraphFile, SavingKeepsTheFilesOrderAndLayout) {
  Graph graph = parseGraph(kUnsortedGraph, "unsorted.json");
  const std::string written = serializeGraph(graph);
  EXPECT_NE(written.find("\"list\": [1.0, 2.0, 3.0]"), std::string::npos) << written;
  // Without a declared row size the dabs are one list; the rest is the file, byte for byte.
  EXPECT_EQ(
      replaceOnce(written, "[0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0]",
                  "[\n          [0.5, 1.0, 1.5, 2.0],\n          [3.0, 4.0, 5.0, 6.0]\n        ]"),
      kUnsortedGraph);
}

TEST(GraphFile, AnEditChangesOnlyItsOwnLinesAndNewKeysFollowTheFilesOnes) {
  Graph graph = parseGraph(kSumGraph, "sum.json");
  const std::string before = serializeGraph(graph);
  graph.nodes.at("b").params["value"] = 4.0;
  graph.nodes.at("a").params["extra"] = std::int64_t(1);
  graph.nodes["aa"] = GraphNode{"test.number", 1, {}};
  const std::string after = serializeGraph(graph);
  // In file order a, b, sum; the new node last although "aa" sorts before "b".
  EXPECT_LT(after.find("\"a\":"), after.find("\"b\":"));
  EXPECT_LT(after.find("\"sum\":"), after.find("\"aa\":"));
  EXPECT_LT(after.find("\"value\": 2"), after.find("\"extra\": 1"));
  // The lines that differ: b's value, a's new param (and the comma it adds), the new node.
  auto lines = [](const std::string& text) {
    std::vector<std::string> out;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);)
      out.push_back(line);
    return out;
  };
  const auto old = lines(before), now = lines(after);
  std::size_t unchanged = 0;
  for (const std::string& line : old)
    unchanged += std::count(now.begin(), now.end(), line) > 0;
  // a's value and the sum node gain a comma; b's value changes.
  EXPECT_EQ(old.size() - unchanged, 3u) << before << after;
  EXPECT_EQ(now.size() - old.size(), 2u) << after;  // "extra"; the "aa" node
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

// Saved graphs go through the same check as every output: a regular file, or a link to one.
TEST(GraphFile, WritesThroughALinkButNeverOverAFifo) {
  const auto dir = test::tempDir("graph-write-special");
  Graph graph = parseGraph(kSumGraph, dir / "g.json");
  const auto fifo = dir / "fifo.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  try {
    writeGraphFile(graph, fifo);
    ADD_FAILURE() << "replaced a FIFO";
  } catch (const GraphError& e) {
    EXPECT_TRUE(test::contains(e.what(), test::quoted(fifo) + ": is a FIFO"));
  }
  EXPECT_TRUE(std::filesystem::is_fifo(fifo));
  std::ofstream(dir / "saved.json") << "{}";
  std::filesystem::create_symlink("saved.json", dir / "link.json");
  writeGraphFile(graph, dir / "link.json");
  EXPECT_TRUE(std::filesystem::is_symlink(dir / "link.json"));
  EXPECT_EQ(readGraphFile(dir / "saved.json").nodes.size(), 3u);
  EXPECT_EQ(std::distance(std::filesystem::directory_iterator(dir), {}), 3);
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

// What nlohmann reports in its own words (a number no double holds, a value of the wrong type)
// becomes a GraphError naming the file, node and param.
TEST(GraphFileErrors, NumberOutOfRangeNamesTheNodeAndParam) {
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": 1e309})")),
            "bad.json: node 'a' param 'value': number out of range: 1e309");
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": [1, -1e400]})")),
            "bad.json: node 'a' param 'value': number out of range: -1e400");
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("typeVersion": 2)", R"("typeVersion": 2e999)")),
            "bad.json: node 'sum' \"typeVersion\": number out of range: 2e999");
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("x": 10)", R"("x": 1e999)")),
            "bad.json: node 'a' ui \"x\": number out of range: 1e999");
  EXPECT_EQ(
      prepareError(replaceOnce(kSumGraph, R"("formatVersion": 1)", R"("formatVersion": 1e999)")),
      "bad.json: \"formatVersion\": number out of range: 1e999");
  EXPECT_EQ(prepareError(R"({"format": "geobrush-graph", "formatVersion": 1,
                             "connections": {"a": 1e999}})"),
            "bad.json: \"connections\": number out of range: 1e999");
  EXPECT_EQ(
      prepareError(replaceOnce(kSumGraph, R"("to": "sum.a"})", R"("to": "sum.a", "x": -1e999})")),
      "bad.json: connection 1: number out of range: -1e999");
  // An integer beyond int64 is not read as what it wraps to (-1 here, inside the range).
  auto huge =
      prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": 18446744073709551615})"));
  EXPECT_NE(huge.find("node 'a' param 'value': 1.8446744073709552e+19 is outside"),
            std::string::npos)
      << huge;
  EXPECT_EQ(
      prepareError(replaceOnce(kSumGraph, R"("typeVersion": 2)", R"("typeVersion": 4294967298)")),
      "bad.json: node 'sum' \"typeVersion\": number out of range: 4294967298");
}

TEST(GraphFileErrors, WrongJsonTypesAreGraphErrorsWithTheirPlace) {
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("x": 10)", R"("x": "left")")),
            "bad.json: node 'a' ui \"x\": must be a number");
  auto object = prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": {"x": 1}})"));
  EXPECT_EQ(object, "bad.json: node 'a' param 'value': an object is not a parameter value");
}

TEST(GraphFileErrors, MalformedJsonNamesWhereItBroke) {
  auto error = prepareError(replaceOnce(kSumGraph, R"("value": 3.5})", R"("value": 3.5.1})"));
  EXPECT_NE(error.find("bad.json: node 'b' param 'value': malformed JSON: parse error at line 5"),
            std::string::npos)
      << error;
}

// A JSON object names each key once: the DOM would keep the last silently.
TEST(GraphFileErrors, DuplicateKeysAreRefusedAtAnyLevel) {
  const std::string twice = replaceOnce(
      kSumGraph, R"("sum": {)",
      R"("a": {"type": "test.number", "typeVersion": 1, "params": {"value": 9}}, "sum": {)");
  EXPECT_EQ(prepareError(twice), "bad.json: node 'a': duplicate key \"a\"");
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("value": 2})", R"("value": 2, "value": 5})")),
            "bad.json: node 'a' param 'value': duplicate key \"value\"");
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("formatVersion": 1,)",
                                     R"("formatVersion": 1, "formatVersion": 1,)")),
            "bad.json: \"formatVersion\": duplicate key \"formatVersion\"");
  EXPECT_EQ(
      prepareError(replaceOnce(kSumGraph, R"("to": "sum.a"})", R"("to": "sum.a", "to": "x.y"})")),
      "bad.json: connection 1: duplicate key \"to\"");
  EXPECT_EQ(prepareError(replaceOnce(kSumGraph, R"("y": -20})", R"("y": -20, "y": 0})")),
            "bad.json: node 'a' ui \"y\": duplicate key \"y\"");
}

TEST(GraphFileErrors, DeepNestingIsRefused) {
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  auto error = prepareError(replaceOnce(kSumGraph, R"("value": 2})", "\"value\": " + deep + "}"));
  EXPECT_EQ(error, "bad.json: node 'a' param 'value': nested deeper than 64 levels");
}

// A NUL ends a path where the file system reads it: the file written would be another one.
TEST(GraphFileErrors, NulInAPathParamIsRefused) {
  const char* json = R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"n": {"type": "test.number", "typeVersion": 1},
              "w": {"type": "test.write_text", "typeVersion": 1, "params": {"path": "a\u0000.txt"}},
              "r": {"type": "test.read_text", "typeVersion": 1, "params": {"path": "b.txt"}}},
    "connections": [{"from": "n.value", "to": "w.value"}]})";
  EXPECT_EQ(prepareError(json),
            "bad.json: node 'w' param 'path': 'a\\x00.txt': a path may not contain a NUL "
            "character");
  EXPECT_EQ(prepareError(replaceOnce(replaceOnce(json, "a\\u0000.txt", "a.txt"), "b.txt",
                                     "b.txt\\u0000.obj")),
            "bad.json: node 'r' param 'path': 'b.txt\\x00.obj': a path may not contain a NUL "
            "character");
}

// Two outputs to one file would each report writing it, and one would be lost.
TEST(GraphFileErrors, TwoOutputsToOneFileAreRefused) {
  const std::string json = R"({"format": "geobrush-graph", "formatVersion": 1,
    "nodes": {"n": {"type": "test.number", "typeVersion": 1},
              "w1": {"type": "test.write_text", "typeVersion": 1, "params": {"path": "out/v.txt"}},
              "w2": {"type": "test.write_text", "typeVersion": 1, "params": {"path": "out/./x/../v.txt"}}},
    "connections": [{"from": "n.value", "to": "w1.value"}, {"from": "n.value", "to": "w2.value"}]})";
  const auto error = prepareError(json);
  EXPECT_NE(error.find("bad.json: node 'w2' param 'path': writes 'out/v.txt', as node 'w1' param "
                       "'path' does"),
            std::string::npos)
      << error;
  // Both at their default, value.txt.
  EXPECT_NE(prepareError(replaceOnce(replaceOnce(json, R"(, "params": {"path": "out/v.txt"})", ""),
                                     R"(, "params": {"path": "out/./x/../v.txt"})", ""))
                .find("node 'w2' param 'path': writes 'value.txt', as node 'w1'"),
            std::string::npos);
  EXPECT_EQ(prepareError(replaceOnce(json, "out/./x/../v.txt", "out/w.txt")), "no error");

  // An absolute path and a relative one meet only in the output folder, once it is known.
  Graph graph =
      parseGraph(replaceOnce(json, "out/./x/../v.txt", "/tmp/results/out/v.txt"), "bad.json");
  EXPECT_NO_THROW(prepareGraph(graph, test::testNodeRegistry()));
  EXPECT_NO_THROW(checkOutputPaths(graph, test::testNodeRegistry(), "/tmp/elsewhere"));
  try {
    checkOutputPaths(graph, test::testNodeRegistry(), "/tmp/results");
    ADD_FAILURE() << "two writers of /tmp/results/out/v.txt";
  } catch (const GraphError& e) {
    EXPECT_TRUE(test::contains(e.what(), "'/tmp/results/out/v.txt', as node 'w1' param 'path'"));
  }
  // A graph being edited may name one file twice for a while.
  Graph editing = parseGraph(json, "editing.json");
  EXPECT_NO_THROW(prepareGraph(editing, test::testNodeRegistry(), false));
}

// Names and texts from the file are quoted escaped, and a long one is cut: one bounded line.
TEST(GraphFileErrors, MessagesEscapeAndBoundWhatTheFileSays) {
  const std::string value = "\\u001b]0;title\\u0007\\n" + std::string(100000, 'x');
  const auto error = prepareError(replaceOnce(
      kSumGraph, R"("type": "test.add", "typeVersion": 2})",
      R"("type": "test.fail", "typeVersion": 1, "params": {"how": ")" + value + "\"}}"));
  EXPECT_TRUE(test::contains(error, "bad.json: node 'sum' param 'how': '\\x1b]0;title\\x07\\nxxx"));
  EXPECT_TRUE(test::contains(error, "xxx... (100011 bytes)' is not one of: none, node_error"));
  EXPECT_LT(error.size(), 1000u);
  for (char c : error)
    EXPECT_GE(static_cast<unsigned char>(c), 0x20) << error;

  Graph graph = parseGraph(kSumGraph, "sum.json");
  prepareGraph(graph, test::testNodeRegistry());
  try {
    setParamFromText(graph, test::testNodeRegistry(), "a.value=1\n2");
    ADD_FAILURE() << "set a value that is no number";
  } catch (const GraphError& e) {
    EXPECT_STREQ(e.what(), "sum.json: node 'a' param 'value': '1\\n2' is not a number");
  }
  try {
    setParamFromText(graph, test::testNodeRegistry(), "a\x1b.value=1");
    ADD_FAILURE() << "set a param of no node";
  } catch (const GraphError& e) {
    EXPECT_STREQ(e.what(),
                 "sum.json: node 'a\\x1b': no node of that name (in --set 'a\\x1b.value=1')");
  }
}

// Devices and pipes have no size: the file is read through the stream, and at most 64 MiB of it.
TEST(GraphFileErrors, AFileOver64MiBIsRefusedBeforeParsing) {
  const auto dir = test::tempDir("graph-huge");
  const auto huge = dir / "huge.json";
  std::ofstream(huge) << kSumGraph;
  std::filesystem::resize_file(huge, (std::size_t(64) << 20) + 1);  // sparse: nothing written
  try {
    readGraphFile(huge);
    ADD_FAILURE() << "parsed a 64 MiB file";
  } catch (const GraphError& e) {
    EXPECT_EQ(e.what(),
              huge.string() + ": larger than 64 MiB: not a graph file (graph files are kilobytes)");
  }
  // Exactly 64 MiB is read (and is no JSON: the padding is NULs).
  std::filesystem::resize_file(huge, std::size_t(64) << 20);
  try {
    readGraphFile(huge);
    ADD_FAILURE() << "parsed NULs";
  } catch (const GraphError& e) {
    EXPECT_TRUE(test::contains(e.what(), "malformed JSON")) << e.what();
  }
  try {
    readGraphFile(dir);
    ADD_FAILURE() << "read a folder";
  } catch (const GraphError& e) {
    EXPECT_EQ(e.what(), dir.string() + ": is a folder, not a graph file");
  }
}

TEST(GraphFile, ReadsAGraphFromAPipe) {
  const auto dir = test::tempDir("graph-fifo");
  const auto fifo = dir / "graph.json";
  ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
  std::thread writer([&] { std::ofstream(fifo) << kSumGraph; });
  Graph graph;
  EXPECT_NO_THROW(graph = readGraphFile(fifo));
  writer.join();
  EXPECT_EQ(graph.nodes.size(), 3u);
}
