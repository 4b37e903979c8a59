// geobrush-studio: the document's open/save round trip, missing plugins, the window's
// evaluation on its worker thread, and the --screenshot command. Runs under xvfb-run.
#include <gtest/gtest.h>

#include <QApplication>
#include <QEventLoop>
#include <QImage>
#include <QTimer>
#include <fstream>
#include <sstream>

#include "studio_document.hpp"
#include "studio_window.hpp"
#include "test_support.hpp"

using namespace geobrush;
using geobrush::studio::NodeState;
using geobrush::studio::StudioDocument;
using geobrush::studio::StudioWindow;

namespace {

std::string bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

std::filesystem::path graphFile(const std::string& name) {
  return test::sourceDir() / "graphs" / name;
}

// Runs the window's evaluation to its end; returns whether it succeeded.
bool evaluateAndWait(StudioWindow& window) {
  bool ok = false;
  QEventLoop loop;
  QObject::connect(&window, &StudioWindow::evaluated, &loop, [&](bool result) {
    ok = result;
    loop.quit();
  });
  QTimer::singleShot(0, &window, [&] { window.evaluate(); });
  QTimer::singleShot(120000, &loop, [&] { loop.quit(); });
  loop.exec();
  return ok;
}

}  // namespace

TEST(StudioDocument, SavingWhatWasOpenedIsByteStable) {
  const auto dir = test::tempDir("studio-round-trip");
  StudioDocument document(test::registry());
  ASSERT_EQ(document.open(graphFile("clone_mountain_sphere.json")), "");
  ASSERT_EQ(document.save(dir / "first.json"), "");
  StudioDocument again(test::registry());
  ASSERT_EQ(again.open(dir / "first.json"), "");
  ASSERT_EQ(again.save(dir / "second.json"), "");
  EXPECT_EQ(bytes(dir / "first.json"), bytes(dir / "second.json"));
  EXPECT_EQ(again.graph().nodes.size(), document.graph().nodes.size());
  EXPECT_EQ(again.graph().connections, document.graph().connections);
}

TEST(StudioDocument, ANodeWithoutItsPluginStaysMarkedAndSavesBackUnchanged) {
  const auto dir = test::tempDir("studio-missing");
  Graph graph = readGraphFile(graphFile("default.json"));
  graph.nodes["from_elsewhere"] = GraphNode{"acme.smoothing", 3, {{"strength", 0.5}}};
  graph.ui["from_elsewhere"] = {10, 20};
  writeGraphFile(graph, dir / "missing.json");
  StudioDocument document(test::registry());
  ASSERT_EQ(document.open(dir / "missing.json"), "");
  EXPECT_EQ(document.missingNodes(), std::set<std::string>{"from_elsewhere"});
  EXPECT_FALSE(document.evaluable());
  const auto statuses = document.statuses(nullptr);
  EXPECT_EQ(statuses.at("from_elsewhere").state, NodeState::Missing);
  EXPECT_NE(statuses.at("from_elsewhere").message.find("acme.smoothing"), std::string::npos);
  ASSERT_EQ(document.save(dir / "saved.json"), "");
  EXPECT_EQ(bytes(dir / "saved.json"), bytes(dir / "missing.json"));
}

TEST(StudioDocument, ABrokenFileIsRefusedAndTheOpenGraphKept) {
  const auto dir = test::tempDir("studio-broken");
  std::ofstream(dir / "broken.json") << "{\"format\": \"geobrush-graph\", \"formatVersion\": 1,";
  std::ofstream(dir / "newer.json")
      << R"({"format": "geobrush-graph", "formatVersion": 99, "nodes": {}, "connections": []})";
  StudioDocument document(test::registry());
  ASSERT_EQ(document.open(graphFile("default.json")), "");
  const std::size_t nodes = document.graph().nodes.size();
  const std::string broken = document.open(dir / "broken.json");
  EXPECT_NE(broken.find("broken.json"), std::string::npos) << broken;
  EXPECT_NE(document.open(dir / "newer.json"), "");
  EXPECT_EQ(document.graph().nodes.size(), nodes);
  EXPECT_EQ(document.path(), graphFile("default.json"));
}

TEST(StudioWindow, EvaluatesOnItsWorkerAndShowsEachNodesState) {
  StudioWindow window(test::registry());
  const auto dir = test::tempDir("studio-evaluate");
  window.setOutputDir(dir);
  ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile("default.json").string())));
  window.show();
  ASSERT_TRUE(evaluateAndWait(window)) << window.lastReport().error;
  EXPECT_TRUE(std::filesystem::exists(dir / "default.obj"));
  const auto statuses = window.document().statuses(&window.lastReport());
  for (const auto& [name, status] : statuses)
    EXPECT_TRUE(status.state == NodeState::Ok || status.state == NodeState::Warning) << name;
  const QImage shot = window.grab().toImage();
  EXPECT_GT(shot.width(), 600);
  // A second evaluation of the unchanged graph is served from the cache.
  ASSERT_TRUE(evaluateAndWait(window));
  EXPECT_EQ(window.lastReport().computed(), 0);
}

TEST(StudioWindow, AFailingNodeIsReportedAndTheWindowStaysUsable) {
  const auto dir = test::tempDir("studio-failing");
  Graph graph = readGraphFile(graphFile("default.json"));
  graph.nodes["load"] = GraphNode{"geobrush.load_mesh", 1, {{"path", std::string("nothing.obj")}}};
  graph.nodes["save_loaded"] =
      GraphNode{"geobrush.save_mesh", 1, {{"path", std::string("loaded.obj")}}};
  graph.connections.push_back({{"load", "mesh"}, {"save_loaded", "mesh"}});
  writeGraphFile(graph, dir / "failing.json");
  StudioWindow window(test::registry());
  window.setOutputDir(dir);
  ASSERT_TRUE(window.openFile(QString::fromStdString((dir / "failing.json").string())));
  EXPECT_FALSE(evaluateAndWait(window));
  const auto statuses = window.document().statuses(&window.lastReport());
  EXPECT_EQ(statuses.at("load").state, NodeState::Error);
  EXPECT_NE(window.lastReport().error.find("nothing.obj"), std::string::npos);
  ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile("default.json").string())));
  EXPECT_TRUE(evaluateAndWait(window));
}

TEST(StudioCommand, WritesAScreenshotOfTheEvaluatedGraph) {
  const auto dir = test::tempDir("studio-screenshot");
  const auto png = dir / "studio.png";
  const std::string command = (test::cliPath().parent_path() / "geobrush-studio").string() + " " +
                              graphFile("default.json").string() + " --out " + dir.string() +
                              " --screenshot " + png.string() + " 2> " + (dir / "err.txt").string();
  EXPECT_EQ(std::system(command.c_str()), 0) << bytes(dir / "err.txt");
  const QImage shot(QString::fromStdString(png.string()));
  EXPECT_GT(shot.width(), 600);
  EXPECT_GT(shot.height(), 400);
  EXPECT_TRUE(std::filesystem::exists(dir / "default.png"));
  const std::string missing = (test::cliPath().parent_path() / "geobrush-studio").string() +
                              " /no/such/graph.json --screenshot " + png.string() + " 2> " +
                              (dir / "err2.txt").string();
  EXPECT_NE(std::system(missing.c_str()), 0);
  EXPECT_NE(bytes(dir / "err2.txt").find("graph.json"), std::string::npos);
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  QApplication app(argc, argv);
  return RUN_ALL_TESTS();
}
