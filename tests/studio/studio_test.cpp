// geobrush-studio: the document's open/save round trip, missing plugins, the window's
// evaluation on its worker thread, and the --screenshot command. Runs under xvfb-run.
#include <gtest/gtest.h>

#include <QAction>
#include <QApplication>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QElapsedTimer>
#include <QEventLoop>
#include <QImage>
#include <QMouseEvent>
#include <QStatusBar>
#include <QTest>
#include <QTimer>
#include <QTreeWidget>
#include <QWheelEvent>
#include <cmath>
#include <fstream>
#include <numeric>
#include <sstream>

#include "canvas_fixtures.hpp"
#include "clone_edits.hpp"
#include "clone_view.hpp"
#include "studio_document.hpp"
#include "studio_window.hpp"
#include "test_support.hpp"

using namespace geobrush;
using geobrush::studio::CloneTool;
using geobrush::studio::kHandleRadiusShare;
using geobrush::studio::NodeEditor;
using geobrush::studio::NodeState;
using geobrush::studio::OutputView;
using geobrush::studio::StudioDocument;
using geobrush::studio::StudioWindow;
using geobrush::studio::Viewport;

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

// Lets the window's evaluations (live, then settling) run to their end.
bool waitUntilIdle(StudioWindow& window, int timeoutMs = 120000) {
  QElapsedTimer timer;
  timer.start();
  QTest::qWait(20);
  while (!window.idle() && timer.elapsed() < timeoutMs)
    QTest::qWait(20);
  return window.idle();
}

// Opens a shipped graph in the window, shown and active, and lets its evaluations end.
bool openShown(StudioWindow& window, const std::string& name) {
  if (!window.openFile(QString::fromStdString(graphFile(name).string()))) return false;
  window.show();
  window.activateWindow();
  return QTest::qWaitForWindowActive(&window) && waitUntilIdle(window);
}

// Where a point shows in a viewport.
QPoint onScreen(const Viewport& view, const Eigen::Vector3d& point) {
  const auto camera = view.camera();
  if (!camera) return {-1, -1};
  const auto at = camera->project(point);
  return at ? QPoint(int(at->x()), int(at->y())) : QPoint(-1, -1);
}

// The pointer moved over a widget with no button held, delivered at once.
void hoverAt(QWidget& widget, QPoint at) {
  QMouseEvent move(QEvent::MouseMove, QPointF(at), widget.mapToGlobal(QPointF(at)), Qt::NoButton,
                   Qt::NoButton, {});
  QApplication::sendEvent(&widget, &move);
}

// A left-button drag in `steps` moves, as a hand makes it.
void drag(QWidget* widget, QPoint from, QPoint to, Qt::KeyboardModifiers modifiers = {},
          int steps = 8) {
  QTest::mousePress(widget, Qt::LeftButton, modifiers, from);
  for (int i = 1; i <= steps; ++i) {
    const QPoint at = from + (to - from) * i / steps;
    QMouseEvent move(QEvent::MouseMove, at, widget->mapToGlobal(at), Qt::NoButton, Qt::LeftButton,
                     modifiers);
    QApplication::sendEvent(widget, &move);
  }
  QTest::mouseRelease(widget, Qt::LeftButton, modifiers, to);
}

std::vector<double> pointsOf(const MeshPtr& mesh) {
  std::vector<double> points;
  if (!mesh) return points;
  for (auto v : mesh->surface.vertices())
    for (int c = 0; c < 3; ++c)
      points.push_back(mesh->surface.point(v)[c]);
  return points;
}

std::vector<double> dabsOf(const StudioDocument& document, const std::string& node) {
  const auto value = document.param(node, "dabs");
  return value ? std::get<std::vector<double>>(*value) : std::vector<double>{};
}

Eigen::Vector3d vec3Of(const StudioDocument& document, const std::string& node,
                       const std::string& param) {
  const auto value = std::get<Vec3>(*document.param(node, param));
  return {value[0], value[1], value[2]};
}

// The Edit menu's Undo command.
QAction* undoAction(StudioWindow& window) {
  for (QAction* action : window.findChildren<QAction*>())
    if (action->text().startsWith("&Undo")) return action;
  return nullptr;
}

// Screenshots a person can look at, kept in the build tree.
void screenshot(QWidget& widget, const std::string& name) {
  const std::filesystem::path dir = GEOBRUSH_SCREENSHOT_DIR;
  std::filesystem::create_directories(dir);
  EXPECT_TRUE(widget.grab().save(QString::fromStdString((dir / name).string()), "PNG")) << name;
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

// A stroke adds one dab row to the file, one line, in the order and layout the file had.
TEST(StudioDocument, SavingAStrokeAddsItsDabRowsAndChangesNothingElse) {
  const auto dir = test::tempDir("studio-stroke-save");
  const std::filesystem::path original = graphFile("clone_mountain_sphere.json");
  const auto copy = dir / "clone.json";
  std::filesystem::copy_file(original, copy);
  StudioDocument document(test::registry());
  ASSERT_EQ(document.open(copy), "");
  const std::string strokes = "strokes";
  ASSERT_EQ(document.graph().nodes.at(strokes).type, "geobrush.strokes");
  auto dabs = std::get<std::vector<double>>(document.graph().nodes.at(strokes).params.at("dabs"));
  dabs.insert(dabs.end(), {0.25, -0.5, 0.125, 1.0});
  ASSERT_EQ(document.setParam(strokes, "dabs", dabs), "");
  ASSERT_EQ(document.save(copy), "");
  std::vector<std::string> before, after;
  for (auto [file, lines] : {std::pair{original, &before}, {copy, &after}}) {
    std::istringstream in(bytes(file));
    for (std::string line; std::getline(in, line);)
      lines->push_back(line);
  }
  ASSERT_EQ(after.size(), before.size() + 1);
  std::size_t added = 0;
  while (added < before.size() && before[added] == after[added])
    ++added;
  // The last row gains a comma; the new row follows it; the rest is unchanged.
  EXPECT_EQ(after[added], before[added] + ",");
  EXPECT_EQ(after[added + 1].substr(after[added + 1].find('[')), "[0.25, -0.5, 0.125, 1.0]");
  EXPECT_TRUE(std::equal(before.begin() + std::ptrdiff_t(added) + 1, before.end(),
                         after.begin() + std::ptrdiff_t(added) + 2));
}

TEST(StudioDocument, ANodeWithoutItsPluginStaysMarkedAndSavesBackUnchanged) {
  const auto dir = test::tempDir("studio-missing");
  Graph graph = readGraphFile(graphFile("relief_cube.json"));
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
  ASSERT_EQ(document.open(graphFile("relief_cube.json")), "");
  const std::size_t nodes = document.graph().nodes.size();
  const std::string broken = document.open(dir / "broken.json");
  EXPECT_NE(broken.find("broken.json"), std::string::npos) << broken;
  EXPECT_NE(document.open(dir / "newer.json"), "");
  EXPECT_EQ(document.graph().nodes.size(), nodes);
  EXPECT_EQ(document.path(), graphFile("relief_cube.json"));
}

TEST(StudioWindow, EvaluatesOnItsWorkerAndShowsEachNodesState) {
  StudioWindow window(test::registry());
  const auto dir = test::tempDir("studio-evaluate");
  window.setOutputDir(dir);
  ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile("relief_cube.json").string())));
  window.show();
  ASSERT_TRUE(evaluateAndWait(window)) << window.lastReport().error;
  EXPECT_TRUE(std::filesystem::exists(dir / "relief_cube.obj"));
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
  Graph graph = readGraphFile(graphFile("relief_cube.json"));
  graph.nodes["load"] = GraphNode{"geobrush.load_mesh", 1, {{"path", std::string("nothing.obj")}}};
  graph.nodes["save_loaded"] =
      GraphNode{"geobrush.save_mesh", 1, {{"path", std::string("loaded.obj")}}};
  graph.connections.push_back({{"load", "mesh"}, {"save_loaded", "mesh"}});
  writeGraphFile(graph, dir / "failing.json");
  StudioWindow window(test::registry());
  window.setOutputDir(dir);
  window.resize(1200, 800);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  ASSERT_TRUE(window.openFile(QString::fromStdString((dir / "failing.json").string())));
  EXPECT_FALSE(evaluateAndWait(window));
  const auto statuses = window.document().statuses(&window.lastReport());
  EXPECT_EQ(statuses.at("load").state, NodeState::Error);
  EXPECT_NE(window.lastReport().error.find("nothing.obj"), std::string::npos);
  EXPECT_TRUE(window.logText().contains("nothing.obj"));
  // The failing node is selected and in view.
  EXPECT_EQ(window.editor().selectedNodes(), std::vector<std::string>{"load"});
  const auto port = window.editor().portInView({"load", "mesh"}, false);
  ASSERT_TRUE(port);
  EXPECT_TRUE(window.editor().viewport()->rect().contains(*port));
  // Another graph opens with its own log; F5 says which files it wrote.
  ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile("relief_cube.json").string())));
  ASSERT_TRUE(waitUntilIdle(window));
  EXPECT_FALSE(window.logText().contains("nothing.obj"));
  EXPECT_TRUE(evaluateAndWait(window));
  ASSERT_FALSE(window.lastReport().filesWritten.empty());
  for (const auto& path : window.lastReport().filesWritten)
    EXPECT_TRUE(window.logText().contains("wrote " + QString::fromStdString(path.string())))
        << path;
}

// --out makes its folder where it is missing, as `geobrush run --out` does.
TEST(StudioCommand, WritesAScreenshotOfTheEvaluatedGraph) {
  const auto dir = test::tempDir("studio-screenshot");
  const auto png = dir / "studio.png";
  const auto outputs = dir / "new" / "outputs";
  const std::string command = (test::cliPath().parent_path() / "geobrush-studio").string() + " " +
                              graphFile("relief_cube.json").string() + " --out " +
                              outputs.string() + " --screenshot " + png.string() + " 2> " +
                              (dir / "err.txt").string();
  EXPECT_EQ(std::system(command.c_str()), 0) << bytes(dir / "err.txt");
  const QImage shot(QString::fromStdString(png.string()));
  EXPECT_GT(shot.width(), 600);
  EXPECT_GT(shot.height(), 400);
  EXPECT_TRUE(std::filesystem::exists(outputs / "relief_cube.png"));
  const std::string missing = (test::cliPath().parent_path() / "geobrush-studio").string() +
                              " /no/such/graph.json --screenshot " + png.string() + " 2> " +
                              (dir / "err2.txt").string();
  EXPECT_NE(std::system(missing.c_str()), 0);
  EXPECT_NE(bytes(dir / "err2.txt").find("graph.json"), std::string::npos);
  // No graph: the empty window.
  const auto empty = dir / "empty.png";
  const std::string bare = (test::cliPath().parent_path() / "geobrush-studio").string() +
                           " --screenshot " + empty.string() + " 2> " + (dir / "err3.txt").string();
  EXPECT_EQ(std::system(bare.c_str()), 0) << bytes(dir / "err3.txt");
  EXPECT_GT(QImage(QString::fromStdString(empty.string())).width(), 600);
}

TEST(StudioDocument, EditsAreCheckedAndUndoable) {
  StudioDocument document(test::registry());
  ASSERT_EQ(document.open(graphFile("relief_cube.json")), "");
  const std::string original = serializeGraph(document.graph());
  std::string load, save, load2;
  ASSERT_EQ(document.addNode("geobrush.load_mesh", 0, 0, &load), "");
  ASSERT_EQ(document.addNode("geobrush.load_mesh", 0, 100, &load2), "");
  ASSERT_EQ(document.addNode("geobrush.save_mesh", 300, 0, &save), "");
  EXPECT_EQ(load, "load_mesh");
  EXPECT_EQ(load2, "load_mesh_2");
  EXPECT_NE(document.addNode("acme.nothing", 0, 0), "");

  // Ports are checked by type, and by existence.
  ASSERT_EQ(document.connect({load, "mesh"}, {save, "mesh"}), "");
  const std::string mismatch = document.connect({"render", "image"}, {save, "mesh"});
  EXPECT_NE(mismatch.find("takes geobrush.Mesh"), std::string::npos) << mismatch;
  EXPECT_NE(document.connect({load, "nothing"}, {save, "mesh"}).find("no output 'nothing'"),
            std::string::npos);
  // A second source for one input replaces the first.
  ASSERT_EQ(document.connect({load2, "mesh"}, {save, "mesh"}), "");
  EXPECT_EQ(document.graph().source(save, "mesh")->from.node, load2);

  // Params: the declaration's range is enforced; an unchanged value is no edit.
  const std::string resolution = document.graph().nodes.begin()->first;
  EXPECT_NE(document.setParam(resolution, "no_such_param", 1.0), "");
  ASSERT_EQ(document.setParam(load, "path", std::string("mesh.obj")), "");
  const std::string afterPath = serializeGraph(document.graph());
  ASSERT_EQ(document.setParam(load, "path", std::string("mesh.obj")), "");
  // Undo and redo say what they change.
  EXPECT_EQ(document.undoText(), "set " + load + ".path");
  EXPECT_TRUE(document.undo());
  EXPECT_NE(serializeGraph(document.graph()), afterPath);
  EXPECT_EQ(document.redoText(), "set " + load + ".path");
  EXPECT_EQ(document.undoText(), "connect " + load2 + ".mesh to " + save + ".mesh");
  EXPECT_TRUE(document.redo());
  EXPECT_EQ(serializeGraph(document.graph()), afterPath);

  ASSERT_EQ(document.removeNodes({load2}), "");
  EXPECT_EQ(document.undoText(), "delete " + load2);
  document.moveNode(save, 10, 20);
  EXPECT_EQ(document.undoText(), "move " + save);
  EXPECT_TRUE(document.undo());
  EXPECT_EQ(document.graph().source(save, "mesh"), nullptr);
  while (document.undo()) {
  }
  EXPECT_EQ(serializeGraph(document.graph()), original);
  EXPECT_FALSE(document.canUndo());
  EXPECT_TRUE(document.canRedo());
}

// The Edit menu names what Undo and Redo change, and the log says what was undone.
TEST(StudioWindow, UndoSaysWhatItUndoes) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile("relief_cube.json").string())));
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_EQ(window.addNode("geobrush.load_mesh"), "");
  QAction* undo = undoAction(window);
  ASSERT_NE(undo, nullptr);
  EXPECT_EQ(undo->text(), "&Undo add load_mesh");
  undo->trigger();
  ASSERT_TRUE(waitUntilIdle(window));
  EXPECT_TRUE(window.logText().contains("undo: add load_mesh"));
  EXPECT_EQ(undo->text(), "&Undo");
  EXPECT_FALSE(undo->isEnabled());
}

// The title marks unsaved changes (undoing back clears the mark); closing, or Quit, asks before
// dropping them and saves where asked to.
TEST(StudioWindow, MarksUnsavedChangesAndAsksBeforeDroppingThem) {
  const auto dir = test::tempDir("studio-unsaved");
  const auto file = dir / "relief_cube.json";
  std::filesystem::copy_file(graphFile("relief_cube.json"), file);
  const std::string original = bytes(file);
  using Choice = StudioWindow::UnsavedChoice;
  int asked = 0;
  Choice answer = Choice::Cancel;
  {
    StudioWindow window(test::registry());
    window.askAboutChanges = [&] {
      ++asked;
      return answer;
    };
    ASSERT_TRUE(window.openFile(QString::fromStdString(file.string())));
    window.show();
    ASSERT_TRUE(waitUntilIdle(window));
    EXPECT_TRUE(window.windowTitle().endsWith("relief_cube.json[*]"));
    EXPECT_FALSE(window.isWindowModified());
    EXPECT_TRUE(window.close());  // nothing to ask about
    EXPECT_EQ(asked, 0);
    window.show();
    window.activateWindow();
    ASSERT_TRUE(QTest::qWaitForWindowActive(&window));

    ASSERT_EQ(window.setParam("shape", "relief", 0.08), "");
    EXPECT_TRUE(window.isWindowModified());
    QTest::keyClick(&window, Qt::Key_Z, Qt::ControlModifier);
    EXPECT_FALSE(window.isWindowModified());
    QTest::keyClick(&window, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
    EXPECT_TRUE(window.isWindowModified());

    EXPECT_FALSE(window.close());
    EXPECT_EQ(asked, 1);
    EXPECT_TRUE(window.isVisible());
    EXPECT_EQ(bytes(file), original);
    answer = Choice::Save;
    EXPECT_TRUE(window.close());
    EXPECT_EQ(asked, 2);
    EXPECT_FALSE(window.isWindowModified());
    ASSERT_TRUE(waitUntilIdle(window));
  }
  const Graph saved = readGraphFile(file);
  EXPECT_EQ(std::get<double>(saved.nodes.at("shape").params.at("relief")), 0.08);

  StudioWindow window(test::registry());
  window.askAboutChanges = [&] {
    ++asked;
    return Choice::Discard;
  };
  ASSERT_TRUE(window.openFile(QString::fromStdString(file.string())));
  window.show();
  ASSERT_TRUE(waitUntilIdle(window));
  const std::string before = bytes(file);
  ASSERT_EQ(window.setParam("shape", "relief", 0.02), "");
  QAction* quit = nullptr;
  for (QAction* action : window.findChildren<QAction*>())
    if (action->text() == "&Quit") quit = action;
  ASSERT_NE(quit, nullptr);
  EXPECT_EQ(quit->shortcut(), QKeySequence(QKeySequence::Quit));
  quit->trigger();
  EXPECT_EQ(asked, 3);
  EXPECT_FALSE(window.isVisible());
  EXPECT_EQ(bytes(file), before);
  ASSERT_TRUE(waitUntilIdle(window));
}

// The radius's arrows and the [ and ] keys shrink and grow it by a quarter whatever the mesh's
// scale, the status bar saying the new radius.
TEST(StudioWindow, TheBrushRadiusStepsWithItsSizeAndFollowsTheBracketKeys) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(openShown(window, "clone_ear_cube_edge.json"));
  auto& panel = window.clonePanel();
  auto* spin = window.findChild<QDoubleSpinBox*>("brushRadius");
  ASSERT_NE(spin, nullptr);
  panel.setBrushRadius(0.08);
  spin->stepBy(1);
  EXPECT_NEAR(panel.brushRadius(), 0.1, 1e-12);
  panel.setBrushRadius(3.2);
  spin->stepBy(-2);
  EXPECT_NEAR(panel.brushRadius(), 2.048, 1e-12);
  panel.setBrushRadius(0.08);
  QTest::keyClick(&window, Qt::Key_BracketRight);
  EXPECT_NEAR(panel.brushRadius(), 0.1, 1e-12);
  EXPECT_TRUE(window.statusBar()->currentMessage().contains("Brush radius 0.1"))
      << window.statusBar()->currentMessage().toStdString();
  QTest::keyClick(&window, Qt::Key_BracketLeft);
  QTest::keyClick(&window, Qt::Key_BracketLeft);
  EXPECT_NEAR(panel.brushRadius(), 0.064, 1e-12);
  ASSERT_TRUE(waitUntilIdle(window));
}

// R resizes the brush with the pointer, which starts on the disc's edge: its distance from a point
// one disc radius to the left sets the radius, written beside the pointer. Esc restores the radius,
// a click keeps it, and neither paints. [ and ] write their radius beside the pointer too.
TEST(StudioWindow, RResizesTheBrushWithThePointer) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(openShown(window, "clone_ear_cube_edge.json"));
  auto& panel = window.clonePanel();
  const auto roles = panel.roles();
  const StudioDocument& document = window.document();
  Viewport& target = panel.targetView();
  panel.setTool(CloneTool::PaintRegion);
  panel.setBrushRadius(0.05);
  const std::vector<double> dabs = dabsOf(document, roles.strokes);
  const QPoint at = onScreen(target, vec3Of(document, roles.targetMap, "origin"));
  hoverAt(target, at);
  ASSERT_FALSE(target.outlines().empty());
  // The disc's radius on the screen, from its outline (the last one drawn).
  const auto camera = target.camera();
  ASSERT_TRUE(camera);
  double sum = 0;
  int count = 0;
  for (const Eigen::Vector3d& point : target.outlines().back().points) {
    const auto p = point.allFinite() ? camera->project(point) : std::nullopt;
    if (!p) continue;
    sum += std::hypot(p->x() - at.x(), p->y() - at.y());
    ++count;
  }
  ASSERT_GT(count, 0);
  const double pixels = sum / count;
  ASSERT_GT(pixels, 2.0);

  // The radius box holds the radius to its decimals.
  auto* box = window.findChild<QDoubleSpinBox*>("brushRadius");
  ASSERT_NE(box, nullptr);
  const double held = 0.5 * std::pow(10.0, -box->decimals());
  QTest::keyClick(&window, Qt::Key_R);
  ASSERT_TRUE(panel.resizingBrush());
  ASSERT_TRUE(target.note());
  hoverAt(target, at + QPoint(10, 0));
  EXPECT_NEAR(panel.brushRadius(), 0.05 * (pixels + 10) / pixels, held);
  hoverAt(target, at + QPoint(-1, 0));
  EXPECT_NEAR(panel.brushRadius(), 0.05 * (pixels - 1) / pixels, held);
  ASSERT_TRUE(target.note());
  EXPECT_TRUE(target.note()->text.contains(QString::number(panel.brushRadius(), 'g', 4)))
      << target.note()->text.toStdString();
  QTest::keyClick(&window, Qt::Key_Escape);
  EXPECT_FALSE(panel.resizingBrush());
  EXPECT_FALSE(target.note());
  EXPECT_EQ(panel.brushRadius(), 0.05);

  hoverAt(target, at);
  QTest::keyClick(&window, Qt::Key_R);
  ASSERT_TRUE(panel.resizingBrush());
  hoverAt(target, at + QPoint(20, 0));
  const double grown = panel.brushRadius();
  EXPECT_NEAR(grown, 0.05 * (pixels + 20) / pixels, held);
  screenshot(target, "brush_resize.png");
  QTest::mouseClick(&target, Qt::LeftButton, {}, at + QPoint(20, 0));
  EXPECT_FALSE(panel.resizingBrush());
  EXPECT_FALSE(target.note());
  EXPECT_EQ(panel.brushRadius(), grown);
  EXPECT_EQ(dabsOf(document, roles.strokes), dabs);
  // ] writes its new radius beside the pointer too, until the pointer moves on.
  hoverAt(target, at);
  QTest::keyClick(&window, Qt::Key_BracketRight);
  ASSERT_TRUE(target.note());
  EXPECT_TRUE(target.note()->text.contains(QString::number(panel.brushRadius(), 'g', 4)));
  hoverAt(target, at + QPoint(3, 0));
  EXPECT_FALSE(target.note());
  // Without a brush under the pointer R says so and changes nothing.
  hoverAt(target, QPoint(2, target.height() - 2));
  QTest::keyClick(&window, Qt::Key_R);
  EXPECT_FALSE(panel.resizingBrush());
  EXPECT_TRUE(window.statusBar()->currentMessage().contains("resize"))
      << window.statusBar()->currentMessage().toStdString();
  ASSERT_TRUE(waitUntilIdle(window));
}

// Wherever the target shows (u, v) lines, on its canvas or on the paste, the region brush shows
// there too: its disc of the shared domain lies on the target canvas at least in part (a sweep
// of the whole view, the target canvas moved along the cube's face); and the surface around the
// moved paste is coloured as its canvas.
TEST(StudioWindow, TheRegionBrushShowsWhereverTheTargetShowsLines) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(openShown(window, "clone_ear_cube_edge.json"));
  auto& panel = window.clonePanel();
  window.setParam(panel.roles().targetMap, "origin", Vec3{1.0, 0.45, 0.7});
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  panel.setTool(CloneTool::PaintRegion);
  const Viewport& target = panel.targetView();
  const studio::LiveView& live = panel.liveView();
  ASSERT_TRUE(live.targetLocator);
  int lined = 0, without = 0;
  for (int y = 2; y < target.height(); y += 6)
    for (int x = 2; x < target.width(); x += 6) {
      const auto hit = target.pick(QPointF(x, y));
      const auto uv = hit ? uvAt(live.target, *hit) : std::nullopt;
      if (!uv) continue;
      ++lined;
      const auto disc = studio::domainCircle(*live.targetLocator, *uv, panel.brushRadius());
      without += std::none_of(disc.begin(), disc.end(),
                              [](const Eigen::Vector3d& p) { return p.allFinite(); });
    }
  EXPECT_GT(lined, 1000);
  EXPECT_EQ(without, 0);
  // Every target vertex beside the moved paste lies on the target canvas: it is drawn in the
  // canvas's colour with its lines, so no band of uncoloured surface surrounds the paste.
  const TriMesh& shown = live.target.mesh->surface;
  const PasteMap& map = *live.values.pasteMap;
  int besidePaste = 0, offCanvas = 0;
  for (auto v : shown.vertices()) {
    if (map.sourceVertex[std::size_t(v.idx())] >= 0) continue;
    bool beside = false;
    for (auto w : shown.vv_range(v))
      beside = beside || map.sourceVertex[std::size_t(w.idx())] >= 0;
    besidePaste += beside;
    offCanvas += beside && !live.target.uv[std::size_t(v.idx())].allFinite();
  }
  EXPECT_GT(besidePaste, 10);
  EXPECT_EQ(offCanvas, 0);
}

// While the target canvas is dragged, the source surface stays the same value and is not drawn
// again, and the target's new surface arrives with its render geometry built on the evaluating
// thread: the UI thread only rasterizes it.
TEST(StudioWindow, MovingTheTargetRedrawsTheTargetAloneFromGeometryPreparedAhead) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(openShown(window, "clone_ear_cube_edge.json"));
  auto& panel = window.clonePanel();
  Viewport& source = panel.sourceView();
  Viewport& target = panel.targetView();
  source.repaint();
  target.repaint();
  const MeshPtr sourceShown = source.surface().mesh;
  const MeshPtr targetShown = target.surface().mesh;
  const qint64 sourceImage = source.image().cacheKey();
  const std::size_t targetBuilds = target.geometryBuilds();
  ASSERT_TRUE(sourceShown && targetShown);
  for (const Vec3& origin : {Vec3{1.0, 0.45, 0.7}, Vec3{1.0, 0.5, 0.65}}) {
    window.setParam(panel.roles().targetMap, "origin", origin);
    ASSERT_TRUE(waitUntilIdle(window));
    ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
    source.repaint();
    target.repaint();
    EXPECT_EQ(source.surface().mesh, sourceShown);
    EXPECT_EQ(source.image().cacheKey(), sourceImage);
    EXPECT_NE(target.surface().mesh, targetShown);
    EXPECT_EQ(target.geometryBuilds(), targetBuilds);
  }
  // A new stroke changes the source's tint: its surface is made and drawn again.
  const std::string strokes = panel.roles().strokes;
  auto dabs =
      std::get<std::vector<double>>(window.document().graph().nodes.at(strokes).params.at("dabs"));
  dabs.insert(dabs.end(), {dabs[0] + 0.01, dabs[1], dabs[2], 1});
  ASSERT_EQ(window.setParam(strokes, "dabs", dabs), "");
  ASSERT_TRUE(waitUntilIdle(window));
  source.repaint();
  EXPECT_NE(source.surface().mesh, sourceShown);
  EXPECT_NE(source.image().cacheKey(), sourceImage);
}

// A clone opens framed on the paste, not on the whole target (Home frames it all, F the paste
// again); the wheel zooms toward the pointer: the point under it stays there.
TEST(StudioWindow, OpensFramedOnThePasteAndZoomsTowardThePointer) {
  StudioWindow window(test::registry());
  window.resize(1000, 600);
  ASSERT_TRUE(openShown(window, "clone_ear_cube_edge.json"));
  Viewport& target = window.clonePanel().targetView();
  ASSERT_TRUE(target.surface().mesh && target.frame());
  const double whole =
      0.5 * geobrush::studio::boundsOf(target.surface().mesh->surface).diagonal().norm();
  // The box of the pasted vertices (those the paste map gives a source vertex).
  const auto& values = window.clonePanel().liveView().values;
  ASSERT_TRUE(values.result && values.pasteMap);
  Eigen::AlignedBox3d pasted;
  for (auto v : values.result->surface.vertices())
    if (values.pasteMap->sourceVertex[std::size_t(v.idx())] >= 0)
      pasted.extend(pointOf(values.result->surface, v));
  const double paste = target.frame()->radius;
  EXPECT_NEAR(paste, 0.5 * pasted.diagonal().norm(), 1e-12 * whole);
  EXPECT_LT(paste, 0.5 * whole);
  QTest::keyClick(&window, Qt::Key_Home);
  EXPECT_NEAR(target.frame()->radius, whole, 1e-12 * whole);
  QTest::keyClick(&window, Qt::Key_F);
  EXPECT_EQ(target.frame()->radius, paste);

  // A point of the plane through the frame's centre, across the view, under a pixel off centre.
  const auto camera = target.camera();
  ASSERT_TRUE(camera);
  const QPointF pixel(0.5 * target.width() + 70, 0.5 * target.height() - 40);
  const auto [eye, centreRay] = camera->ray(0.5 * target.width(), 0.5 * target.height());
  const auto [_, pixelRay] = camera->ray(pixel.x(), pixel.y());
  const auto& c = target.frame()->center;
  const double depth = (Eigen::Vector3d(c[0], c[1], c[2]) - eye).dot(centreRay);
  const Eigen::Vector3d point = eye + depth / pixelRay.dot(centreRay) * pixelRay;
  QWheelEvent wheel(pixel, target.mapToGlobal(pixel), {}, {0, 360}, Qt::NoButton, {},
                    Qt::NoScrollPhase, false);
  QApplication::sendEvent(&target, &wheel);
  EXPECT_GT(target.view().zoom, 1.5);
  const auto moved = target.camera()->project(point);
  ASSERT_TRUE(moved);
  EXPECT_NEAR(moved->x(), pixel.x(), 1e-6);
  EXPECT_NEAR(moved->y(), pixel.y(), 1e-6);
  ASSERT_TRUE(waitUntilIdle(window));
}

// The (u, v) lines (L), the origins' axes (A) and the wireframe (W) toggle; Clean (C) shows the
// paste alone: no lines, no axes, no canvas colours.
TEST(StudioWindow, TheLinesAxesAndCanvasColoursToggleAndCleanShowsThePasteAlone) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(openShown(window, "clone_ear_cube_edge.json"));
  auto& panel = window.clonePanel();
  Viewport& source = panel.sourceView();
  Viewport& target = panel.targetView();
  const auto& values = panel.liveView().values;
  ASSERT_TRUE(values.result);
  EXPECT_EQ(target.lines().size(), 2u);
  EXPECT_FALSE(source.outlines().empty());          // the origin's axes
  EXPECT_NE(target.surface().mesh, values.result);  // coloured by its canvas

  QTest::keyClick(&window, Qt::Key_L);
  EXPECT_TRUE(source.lines().empty());
  EXPECT_TRUE(target.lines().empty());
  QTest::keyClick(&window, Qt::Key_L);
  EXPECT_EQ(source.lines().size(), 2u);
  QTest::keyClick(&window, Qt::Key_A);
  EXPECT_TRUE(source.outlines().empty());
  EXPECT_TRUE(target.outlines().empty());
  QTest::keyClick(&window, Qt::Key_A);
  EXPECT_FALSE(target.outlines().empty());

  // Wireframe (W) draws the edges: the picture changes, the surface shown does not.
  EXPECT_FALSE(target.wireframe());
  target.repaint();
  const QImage shaded = target.image();
  QTest::keyClick(&window, Qt::Key_W);
  EXPECT_TRUE(source.wireframe() && target.wireframe());
  target.repaint();
  EXPECT_NE(target.image(), shaded);
  QTest::keyClick(&window, Qt::Key_W);
  EXPECT_FALSE(target.wireframe());

  QTest::keyClick(&window, Qt::Key_C);
  EXPECT_TRUE(source.lines().empty() && target.lines().empty());
  EXPECT_TRUE(source.outlines().empty() && target.outlines().empty());
  EXPECT_EQ(target.surface().mesh, values.result);
  EXPECT_EQ(source.surface().mesh, values.sourceMesh);
  // Back to the canvas colours from the colour box.
  EXPECT_TRUE(panel.colourTargetBy(""));
  EXPECT_NE(target.surface().mesh, values.result);
  ASSERT_TRUE(waitUntilIdle(window));
}

// The node editor frames the whole graph on opening (every box in view, the fill graph's too),
// and the wheel zooms it.
TEST(StudioWindow, TheNodeEditorFramesTheGraphAndZooms) {
  for (const char* name : {"fill_bunny_small_back.json", "clone_ear_cube_edge.json"}) {
    StudioWindow window(test::registry());
    window.resize(1200, 800);
    window.show();
    ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
    ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile(name).string())));
    QTest::qWait(20);
    NodeEditor& editor = window.editor();
    for (const auto& [node, _] : window.document().graph().nodes) {
      const auto& decl = *test::registry().find(window.document().graph().nodes.at(node).type);
      if (decl.outputs.empty()) continue;
      const auto port = editor.portInView({node, decl.outputs.front().name}, false);
      ASSERT_TRUE(port) << name << ": " << node;
      EXPECT_TRUE(editor.viewport()->rect().contains(*port)) << name << ": " << node;
    }
    const double before = editor.transform().m11();
    const QPointF centre = editor.viewport()->rect().center();
    QWheelEvent wheel(centre, editor.viewport()->mapToGlobal(centre), {}, {0, 240}, Qt::NoButton,
                      {}, Qt::NoScrollPhase, false);
    QApplication::sendEvent(editor.viewport(), &wheel);
    EXPECT_NEAR(editor.transform().m11(), before * 1.15 * 1.15, 1e-9) << name;
    ASSERT_TRUE(waitUntilIdle(window));
  }
}

// A graph without a clone shows a node's mesh: after F5 the graph's result (the mesh that is
// saved and rendered), the selected node's mesh (or picture) on a click, and a param edit of the
// node shown re-evaluates it live.
TEST(StudioWindow, AGraphWithoutACloneShowsTheResultOrTheSelectedNodesMesh) {
  StudioWindow window(test::registry());
  window.resize(1200, 800);
  window.setOutputDir(test::tempDir("studio-output-view"));
  ASSERT_TRUE(openShown(window, "relief_cube.json"));
  OutputView& output = window.outputView();
  EXPECT_TRUE(output.isVisible());
  EXPECT_FALSE(window.clonePanel().isVisible());
  EXPECT_FALSE(output.shown());
  ASSERT_TRUE(evaluateAndWait(window));
  ASSERT_TRUE(output.shown());
  EXPECT_EQ(*output.shown(), (Endpoint{"pose", "mesh"}));
  EXPECT_EQ(output.caption(), "pose.mesh");
  const MeshPtr posed =
      std::dynamic_pointer_cast<const Mesh>(window.evaluator().output("pose", "mesh"));
  EXPECT_EQ(output.viewport().surface().mesh, posed);
  // Drawn: the framed mesh covers a good part of the view.
  QTest::qWait(50);
  const QImage drawn = output.viewport().grab().toImage();
  const QRgb background = drawn.pixel(2, 2);
  int covered = 0;
  for (int y = 0; y < drawn.height(); y += 4)
    for (int x = 0; x < drawn.width(); x += 4)
      covered += drawn.pixel(x, y) != background;
  EXPECT_GT(covered, drawn.width() * drawn.height() / 16 / 10);
  screenshot(window, "output_view.png");
  // The node editor, framed as the graph opened, stays framed as the output view takes its share
  // of the window: the graph fills its width or its height, or shows at full size.
  NodeEditor& editor = window.editor();
  const QRect graph = editor.mapFromScene(editor.sceneRect()).boundingRect();
  const QSize room = editor.viewport()->size();
  EXPECT_TRUE(graph.width() > 0.9 * room.width() || graph.height() > 0.9 * room.height() ||
              editor.transform().m11() == 1.0)
      << graph.width() << " x " << graph.height() << " in " << room.width() << " x "
      << room.height();

  window.selectNode("shape");
  ASSERT_TRUE(output.shown());
  EXPECT_EQ(*output.shown(), (Endpoint{"shape", "mesh"}));
  EXPECT_EQ(output.viewport().surface().mesh,
            std::dynamic_pointer_cast<const Mesh>(window.evaluator().output("shape", "mesh")));
  // The render node shows its picture; a node with neither a mesh nor an image, the result.
  window.selectNode("render");
  EXPECT_EQ(*output.shown(), (Endpoint{"render", "image"}));
  EXPECT_TRUE(output.showsImage());
  EXPECT_EQ(output.caption(), "render.image");
  window.selectNode("save");
  EXPECT_EQ(*output.shown(), (Endpoint{"pose", "mesh"}));
  EXPECT_FALSE(output.showsImage());

  // Shown again and edited: the change reaches the view without F5.
  window.selectNode("shape");
  const auto before = output.viewport().surface().mesh;
  EXPECT_EQ(window.setParam("shape", "relief", 0.1), "");
  ASSERT_TRUE(waitUntilIdle(window));
  const auto after = output.viewport().surface().mesh;
  ASSERT_TRUE(after);
  EXPECT_NE(after, before);
  EXPECT_NE(pointsOf(after), pointsOf(before));
}

// With a handle edit's template shown, a left drag is a handle edit: the press adds a row whose
// handle is the point picked, the drag moves it in the plane facing the view, the template follows
// live while the boundary stays, and one Undo takes the whole drag back.
TEST(StudioWindow, DraggingOnAHandleEditsTemplateMovesAHandleLive) {
  const auto dir = test::tempDir("studio-handle-drag");
  {
    Graph graph;
    graph.nodes["plane"] = GraphNode{
        "geobrush.primitive",
        1,
        {{"shape", std::string("plane")}, {"size", 2.0}, {"resolution", std::int64_t(24)}}};
    graph.nodes["edit"] = GraphNode{"geobrush.handle_edit", 1, {}};
    graph.connections = {{{"plane", "mesh"}, {"edit", "template"}}};
    std::ofstream(dir / "handle.json") << serializeGraph(graph, &test::registry());
  }
  StudioWindow window(test::registry());
  window.resize(1200, 800);
  ASSERT_TRUE(window.openFile(QString::fromStdString((dir / "handle.json").string())));
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  ASSERT_TRUE(evaluateAndWait(window));
  window.selectNode("edit");
  OutputView& output = window.outputView();
  ASSERT_TRUE(output.shown());
  ASSERT_EQ(*output.shown(), (Endpoint{"edit", "template"}));
  const MeshPtr before = output.viewport().surface().mesh;
  QTest::qWait(50);
  const QPoint centre = onScreen(output.viewport(), {0, 0, 0});
  ASSERT_TRUE(output.viewport().rect().contains(centre));
  drag(&output.viewport(), centre, centre + QPoint(0, -60));
  ASSERT_TRUE(waitUntilIdle(window));

  const auto rows = std::get<std::vector<double>>(*window.document().param("edit", "edits"));
  ASSERT_EQ(rows.size(), 11u);
  const Eigen::Vector3d handle(rows[0], rows[1], rows[2]), moved(rows[4], rows[5], rows[6]);
  EXPECT_LT(handle.norm(), 0.05);  // picked where the pointer pressed
  EXPECT_NEAR(rows[3], kHandleRadiusShare * boundingDiagonal(before->surface), 1e-12);
  // The drag moved the handle.
  EXPECT_GT(moved.norm(), 0.05);
  const MeshPtr after = output.viewport().surface().mesh;
  ASSERT_TRUE(after);
  ASSERT_EQ(after->surface.n_vertices(), before->surface.n_vertices());
  double largest = 0;
  for (auto v : after->surface.vertices()) {
    const Eigen::Vector3d d = toEigen(after->surface.point(v)) - toEigen(before->surface.point(v));
    largest = std::max(largest, d.norm());
    if (after->surface.is_boundary(v)) {
      EXPECT_EQ(d.norm(), 0.0);
    }
  }
  EXPECT_NEAR(largest, moved.norm(), 1e-9);  // the handle's vertex moves by the translation
  // The drag is one edit.
  QAction* undo = undoAction(window);
  ASSERT_NE(undo, nullptr);
  EXPECT_EQ(undo->text(), "&Undo set edit.edits");
  undo->trigger();
  EXPECT_TRUE(std::get<std::vector<double>>(*window.document().param("edit", "edits")).empty());
  ASSERT_TRUE(waitUntilIdle(window));
}

// Warnings of live evaluations reach the log when they appear (not only on F5), once while they
// stay.
TEST(StudioWindow, LiveEditsLogTheirWarningsOnce) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(openShown(window, "compare_mountain_sphere_dpm.json"));
  const std::string strokes = window.clonePanel().roles().strokes;
  ASSERT_FALSE(strokes.empty());
  ASSERT_EQ(window.setParam(strokes, "dabs", std::vector<double>{}), "");
  ASSERT_TRUE(waitUntilIdle(window));
  const QString log = window.logText();
  EXPECT_EQ(log.count("the region is empty"), 1) << log.toStdString();
  // Another edit that leaves the region empty: the warning stays, and is not logged again.
  const std::string canvas = window.clonePanel().roles().sourceCanvas;
  const Eigen::Vector3d origin = vec3Of(window.document(), canvas, "origin");
  ASSERT_EQ(window.setParam(canvas, "origin", Vec3{origin.x(), origin.y() + 0.01, origin.z()}), "");
  ASSERT_TRUE(waitUntilIdle(window));
  bool stillWarns = false;
  for (const auto& run : window.lastReport().runs)
    for (const auto& warning : run.warnings)
      stillWarns |= warning.find("the region is empty") != std::string::npos;
  EXPECT_TRUE(stillWarns);
  EXPECT_EQ(window.logText().count("the region is empty"), 1) << window.logText().toStdString();
}

TEST(StudioDocument, AConnectionThatClosesACycleIsRefused) {
  StudioDocument document(test::registry());
  ASSERT_EQ(document.open(graphFile("relief_cube.json")), "");
  std::string a, b;
  ASSERT_EQ(document.addNode("geobrush.transform", 0, 0, &a), "");
  ASSERT_EQ(document.addNode("geobrush.transform", 0, 0, &b), "");
  ASSERT_EQ(document.connect({a, "mesh"}, {b, "mesh"}), "");
  const std::string cycle = document.connect({b, "mesh"}, {a, "mesh"});
  EXPECT_NE(cycle.find("cycle"), std::string::npos) << cycle;
  EXPECT_EQ(document.graph().source(a, "mesh"), nullptr);
}

// Scripted input: a node added from the palette's action, a drag from an output port to an input
// port connects them, undo takes it back, Delete removes the selected node.
TEST(StudioWindow, MouseAndKeysEditTheGraph) {
  StudioWindow window(test::registry());
  ASSERT_TRUE(window.openFile(QString::fromStdString(graphFile("relief_cube.json").string())));
  window.show();
  window.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window));
  ASSERT_EQ(window.addNode("geobrush.transform"), "");
  QTest::qWait(50);
  const std::string shape = "shape";
  ASSERT_TRUE(window.document().graph().nodes.count(shape));
  NodeEditor& editor = window.editor();
  const auto from = editor.portInView({shape, "mesh"}, false);
  const auto to = editor.portInView({"transform", "mesh"}, true);
  ASSERT_TRUE(from && to);
  QWidget* viewport = editor.viewport();
  QTest::mousePress(viewport, Qt::LeftButton, {}, *from);
  QTest::mouseMove(viewport, (*from + *to) / 2);
  QTest::mouseMove(viewport, *to);
  QTest::mouseRelease(viewport, Qt::LeftButton, {}, *to);
  QTest::qWait(50);
  const Connection* made = window.document().graph().source("transform", "mesh");
  ASSERT_NE(made, nullptr);
  EXPECT_EQ(made->from.node, shape);

  QTest::keyClick(window.editor().viewport(), Qt::Key_Z, Qt::ControlModifier);
  QTest::qWait(50);
  EXPECT_EQ(window.document().graph().source("transform", "mesh"), nullptr);

  // Clicking a node shows its params; choosing another value edits the graph.
  const auto shapeOut = editor.portInView({shape, "mesh"}, false);
  ASSERT_TRUE(shapeOut);
  // Offsets in the scene's units, as the editor shows them.
  const auto inView = [&](double x, double y) {
    const double scale = editor.transform().m11();
    return QPoint(int(std::lround(x * scale)), int(std::lround(y * scale)));
  };
  QTest::mouseClick(viewport, Qt::LeftButton, {}, *shapeOut + inView(-60, -20));
  QTest::qWait(50);
  // The parameter panel's choice (the clone panel's colour choices aside).
  QComboBox* choice = nullptr;
  for (QComboBox* box : window.findChildren<QComboBox*>())
    if (box->objectName() != "sourceColour" && box->objectName() != "targetColour") choice = box;
  ASSERT_NE(choice, nullptr);
  EXPECT_EQ(choice->currentText(), "rounded_cube");
  choice->setCurrentText("torus");
  emit choice->textActivated("torus");
  QTest::qWait(50);
  EXPECT_EQ(std::get<std::string>(window.document().graph().nodes.at(shape).params.at("shape")),
            "torus");

  // Select the new node by clicking its title, then delete it.
  const auto title = editor.portInView({"transform", "mesh"}, true);
  ASSERT_TRUE(title);
  QTest::mouseClick(viewport, Qt::LeftButton, {}, *title + inView(40, -12));
  QTest::keyClick(viewport, Qt::Key_Delete);
  QTest::qWait(50);
  EXPECT_FALSE(window.document().graph().nodes.count("transform"));
}

// On a flat canvas with uv = (x, y): rays hit where the plane says, the (u, v) under a hit is the
// point's (x, y), a domain circle lies on the plane at its radius, the painted region is tinted.
TEST(CloneView, PicksAndDrawsOnAFlatCanvasAsTheGeometrySays) {
  using namespace geobrush::studio;
  const auto map = test::heightFieldParameterization(20, [](double, double) { return 0.0; });
  // The canvas covers its whole mesh.
  auto canvas = std::make_shared<Canvas>(*map->canvas);
  canvas->source = std::make_shared<const Mesh>(canvas->surface);
  canvas->sourceVertex.resize(canvas->surface.n_vertices());
  std::iota(canvas->sourceVertex.begin(), canvas->sourceVertex.end(), 0);
  map->canvas = canvas;
  CloneValues values;
  values.sourceMesh = canvas->source;
  values.sourceMap = map;
  auto strokes = std::make_shared<Strokes>();
  strokes->dabs.push_back({Eigen::Vector2d(0, 0), 0.5, false});
  values.strokes = strokes;
  const ShownSurface shown = showSource(values);
  ASSERT_TRUE(shown.mesh);

  const auto hit = castRay(shown.mesh->surface, {0.2, 0.3, 5}, {0, 0, -1});
  ASSERT_TRUE(hit);
  EXPECT_TRUE(hit->point.isApprox(Eigen::Vector3d(0.2, 0.3, 0), 1e-12));
  EXPECT_NEAR(hit->distance, 5, 1e-12);
  EXPECT_TRUE(hit->normal.isApprox(Eigen::Vector3d(0, 0, 1), 1e-12));
  const auto uv = uvAt(shown, *hit);
  ASSERT_TRUE(uv);
  EXPECT_TRUE(uv->isApprox(Eigen::Vector2d(0.2, 0.3), 1e-12));
  EXPECT_FALSE(castRay(shown.mesh->surface, {3, 3, 5}, {0, 0, -1}));
  // From below, the normal turns towards the ray's origin.
  EXPECT_TRUE(castRay(shown.mesh->surface, {0.2, 0.3, -5}, {0, 0, 1})
                  ->normal.isApprox(Eigen::Vector3d(0, 0, -1), 1e-12));

  const DomainLocator locator(*map);
  for (const Eigen::Vector3d& p : domainCircle(locator, {0.1, 0}, 0.3)) {
    EXPECT_NEAR((p - Eigen::Vector3d(0.1, 0, 0)).norm(), 0.3, 1e-9);
    EXPECT_NEAR(p.z(), 0, 1e-12);
  }
  // Past the canvas's edge (x = 1) the circle has gaps.
  int gaps = 0;
  for (const Eigen::Vector3d& p : domainCircle(locator, {0.9, 0}, 0.3))
    gaps += !p.allFinite();
  EXPECT_GT(gaps, 5);
  EXPECT_LT(gaps, 30);
  // Inside the dab every vertex is tinted, outside none is.
  CloneValues unpainted = values;
  unpainted.strokes = nullptr;
  const ShownSurface shownPlain = showSource(unpainted);
  const auto& plain = shownPlain.mesh->vertexColors;
  const auto& colors = shown.mesh->vertexColors;
  int inside = 0;
  for (auto v : shown.mesh->surface.vertices()) {
    const auto& p = shown.mesh->surface.point(v);
    const bool tinted = colors[v.idx()] != plain[v.idx()];
    const double r = std::hypot(p[0], p[1]);
    if (std::abs(r - 0.5) > 1e-9) {  // the rim rounds either way
      EXPECT_EQ(tinted, r < 0.5) << p;
    }
    inside += tinted;
  }
  EXPECT_GT(inside, 10);
}

TEST(CloneView, FindsTheRolesOfEveryCloneGraph) {
  for (const char* name :
       {"clone_mountain_sphere.json", "clone_ear_cube_edge.json", "fill_bunny_small_back.json",
        "compare_mountain_sphere_variational.json", "compare_mountain_sphere_dpm.json",
        "compare_mountain_sphere_dpm_literal.json"}) {
    SCOPED_TRACE(name);
    const auto roles = geobrush::studio::findClone(readGraphFile(graphFile(name)));
    ASSERT_TRUE(roles.found());
    EXPECT_EQ(roles.roi, "roi");
    EXPECT_EQ(roles.strokes, "strokes");
    EXPECT_EQ(roles.sourceMap, "source_map");
    EXPECT_EQ(roles.targetMap, "target_map");
    EXPECT_EQ(roles.sourceCanvas, "source_canvas");
    EXPECT_EQ(roles.sourceMesh.node, "source_mesh");
    EXPECT_EQ(roles.targetMesh.node, "target_mesh");
    EXPECT_FALSE(roles.paste.empty());
  }
  EXPECT_FALSE(geobrush::studio::findClone(readGraphFile(graphFile("relief_cube.json"))).found());
}

// The paper's session, scripted with mouse events on the viewports: place both canvases, paint a
// region stroke on the target, undo and redo it, save, and run the saved file headless.
TEST(StudioWindow, APaintingSessionEditsTheGraphAndRunsTheSameHeadless) {
  const auto dir = test::tempDir("studio-painting");
  StudioWindow window(test::registry());
  window.setOutputDir(dir / "live");
  std::filesystem::create_directories(dir / "live");
  ASSERT_TRUE(
      window.openFile(QString::fromStdString(graphFile("clone_ear_cube_edge.json").string())));
  window.show();
  window.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window));
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  auto& panel = window.clonePanel();
  const auto roles = panel.roles();
  ASSERT_TRUE(roles.found());
  Viewport& source = panel.sourceView();
  Viewport& target = panel.targetView();
  ASSERT_TRUE(source.surface().mesh && target.surface().mesh);
  const StudioDocument& document = window.document();
  screenshot(window, "studio_opened.png");

  // Source origin: a click where the origin shows puts it on the surface point there.
  const Eigen::Vector3d sourceOrigin = vec3Of(document, roles.sourceCanvas, "origin");
  panel.setTool(CloneTool::SourceOrigin);
  const QPoint originPixel = onScreen(source, sourceOrigin);
  QTest::mouseClick(&source, Qt::LeftButton, {}, originPixel);
  const Eigen::Vector3d clicked = vec3Of(document, roles.sourceCanvas, "origin");
  EXPECT_NE(clicked, sourceOrigin);
  EXPECT_LT((clicked - sourceOrigin).norm(), 0.02);
  // The canvas brush adds dabs along a drag; all of it undoes as one edit.
  panel.setTool(CloneTool::PaintCanvas);
  panel.setBrushRadius(0.1);
  const std::size_t canvasDabs = dabsOf(document, roles.sourceCanvas).size();
  drag(&source, originPixel, originPixel + QPoint(30, 20));
  const std::vector<double> paintedCanvas = dabsOf(document, roles.sourceCanvas);
  EXPECT_GT(paintedCanvas.size(), canvasDabs + 4);
  QTest::keyClick(&window, Qt::Key_Z, Qt::ControlModifier);
  EXPECT_EQ(dabsOf(document, roles.sourceCanvas).size(), canvasDabs);
  EXPECT_EQ(vec3Of(document, roles.sourceCanvas, "origin"), clicked);
  QTest::keyClick(&window, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
  EXPECT_EQ(dabsOf(document, roles.sourceCanvas), paintedCanvas);
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;

  // Target origin: a click where it shows.
  panel.setTool(CloneTool::TargetOrigin);
  const Eigen::Vector3d targetOrigin = vec3Of(document, roles.targetMap, "origin");
  const QPoint targetPixel = onScreen(target, targetOrigin);
  QTest::mouseClick(&target, Qt::LeftButton, {}, targetPixel);
  // The ear pasted there is what the click hits: its (u, v) leads back to the cube (side 2)
  // near the old origin.
  const Eigen::Vector3d newOrigin = vec3Of(document, roles.targetMap, "origin");
  EXPECT_NE(newOrigin, targetOrigin);
  EXPECT_LT((newOrigin - targetOrigin).norm(), 0.25);
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  const std::vector<double> before = pointsOf(
      std::dynamic_pointer_cast<const Mesh>(window.evaluator().output(roles.paste, "mesh")));
  ASSERT_FALSE(before.empty());

  // A region stroke on the target canvas: dabs in the shared domain, a different clone.
  panel.setTool(CloneTool::PaintRegion);
  panel.setBrushRadius(0.05);
  const std::size_t regionDabs = dabsOf(document, roles.strokes).size();
  const QPoint strokeStart = onScreen(target, vec3Of(document, roles.targetMap, "origin"));
  drag(&target, strokeStart, strokeStart + QPoint(40, 10));
  const std::vector<double> strokeDabs = dabsOf(document, roles.strokes);
  EXPECT_GE(strokeDabs.size(), regionDabs + 8);
  for (std::size_t i = regionDabs; i < strokeDabs.size(); i += 4) {
    EXPECT_EQ(strokeDabs[i + 2], 0.05);
    EXPECT_EQ(strokeDabs[i + 3], 1.0);
  }
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  const std::vector<double> painted = pointsOf(
      std::dynamic_pointer_cast<const Mesh>(window.evaluator().output(roles.paste, "mesh")));
  EXPECT_NE(painted, before);
  // The status counts what the stroke's evaluations computed, not only the last one's.
  const QString status = window.statusBar()->currentMessage();
  EXPECT_TRUE(status.contains("nodes computed since the last edit")) << status.toStdString();
  EXPECT_FALSE(status.contains(": 0 nodes")) << status.toStdString();
  // The brush shows on both surfaces while hovering.
  QTest::mouseMove(&target, strokeStart + QPoint(6, 2));
  screenshot(window, "studio_painted.png");

  // Undo takes the whole stroke back, and the mesh with it, bit for bit; redo brings both back.
  QTest::keyClick(&window, Qt::Key_Z, Qt::ControlModifier);
  EXPECT_EQ(dabsOf(document, roles.strokes).size(), regionDabs);
  ASSERT_TRUE(waitUntilIdle(window));
  EXPECT_EQ(pointsOf(std::dynamic_pointer_cast<const Mesh>(
                window.evaluator().output(roles.paste, "mesh"))),
            before);
  QTest::keyClick(&window, Qt::Key_Z, Qt::ControlModifier | Qt::ShiftModifier);
  EXPECT_EQ(dabsOf(document, roles.strokes), strokeDabs);
  ASSERT_TRUE(waitUntilIdle(window));
  EXPECT_EQ(pointsOf(std::dynamic_pointer_cast<const Mesh>(
                window.evaluator().output(roles.paste, "mesh"))),
            painted);

  // The region brush paints on the source canvas too; Shift subtracts.
  const QPoint onSource = onScreen(source, vec3Of(document, roles.sourceCanvas, "origin"));
  drag(&source, onSource, onSource + QPoint(3, 3), Qt::ShiftModifier, 2);
  const std::vector<double> erased = dabsOf(document, roles.strokes);
  ASSERT_GT(erased.size(), strokeDabs.size());
  EXPECT_EQ(erased.back(), -1.0);
  // Off the surface nothing is painted, and the status bar says why.
  window.statusBar()->clearMessage();
  QTest::mouseClick(&target, Qt::LeftButton, {}, QPoint(4, target.height() - 4));
  EXPECT_EQ(dabsOf(document, roles.strokes), erased);
  EXPECT_FALSE(window.statusBar()->currentMessage().isEmpty());

  // Dragging the target canvas moves its origin over the surface and keeps the strokes; with
  // Shift the drag turns it (0.5 degrees a pixel), with Ctrl it scales it.
  panel.setTool(CloneTool::MoveTarget);
  const Eigen::Vector3d beforeMove = vec3Of(document, roles.targetMap, "origin");
  const QPoint grab = onScreen(target, beforeMove) + QPoint(6, 0);
  drag(&target, grab, grab + QPoint(0, 20));
  EXPECT_GT((vec3Of(document, roles.targetMap, "origin") - beforeMove).norm(), 0.02);
  EXPECT_EQ(dabsOf(document, roles.strokes), erased);
  const double angle = std::get<double>(*document.param(roles.targetMap, "angle"));
  drag(&target, grab, grab + QPoint(20, 0), Qt::ShiftModifier);
  EXPECT_NEAR(std::get<double>(*document.param(roles.targetMap, "angle")), angle + 10, 1e-9);
  const double scale = std::get<double>(*document.param(roles.targetMap, "scale"));
  drag(&target, grab, grab + QPoint(0, 10), Qt::ControlModifier);  // down: smaller
  EXPECT_NEAR(std::get<double>(*document.param(roles.targetMap, "scale")), scale * std::exp(-0.1),
              1e-9);
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  screenshot(window, "studio_moved.png");

  // Saved elsewhere (the mesh paths follow) and run headless: the same mesh, byte for byte.
  ASSERT_TRUE(window.saveFile(QString::fromStdString((dir / "session.json").string())));
  std::filesystem::create_directories(dir / "studio");
  window.setOutputDir(dir / "studio");
  ASSERT_TRUE(evaluateAndWait(window)) << window.lastReport().error;
  ASSERT_TRUE(waitUntilIdle(window));
  const std::string run = test::cliPath().string() + " run " + (dir / "session.json").string() +
                          " --out " + (dir / "cli").string() + " --quiet";
  std::filesystem::create_directories(dir / "cli");
  ASSERT_EQ(std::system(run.c_str()), 0);
  const std::string saved = "ear_on_cube_edge.obj";
  ASSERT_TRUE(std::filesystem::exists(dir / "studio" / saved));
  EXPECT_EQ(bytes(dir / "studio" / saved), bytes(dir / "cli" / saved));
  screenshot(window, "studio_saved.png");
}

namespace {

// Adds a node of `type` as a double click in the palette does; returns its name.
std::string addNode(StudioWindow& window, const std::string& type) {
  const auto before = window.document().graph().nodes;
  EXPECT_EQ(window.addNode(type), "");
  for (const auto& [name, node] : window.document().graph().nodes)
    if (!before.count(name)) return name;
  return {};
}

// Drags from an output port to an input port in the node editor, both scrolled into view.
void connectByMouse(StudioWindow& window, const Endpoint& from, const Endpoint& to) {
  QTest::qWait(10);  // the editor shows the last edit after the event that made it
  NodeEditor& editor = window.editor();
  auto a = editor.portInView(from, false), b = editor.portInView(to, true);
  ASSERT_TRUE(a && b) << from.node << "." << from.port << " -> " << to.node << "." << to.port;
  editor.centerOn(editor.mapToScene((*a + *b) / 2));
  a = editor.portInView(from, false);
  b = editor.portInView(to, true);
  QWidget* view = editor.viewport();
  ASSERT_TRUE(view->rect().contains(*a) && view->rect().contains(*b));
  QTest::mousePress(view, Qt::LeftButton, {}, *a);
  QTest::mouseMove(view, (*a + *b) / 2);
  QTest::mouseMove(view, *b);
  QTest::mouseRelease(view, Qt::LeftButton, {}, *b);
  const Connection* made = window.document().graph().source(to.node, to.port);
  ASSERT_NE(made, nullptr) << to.node << "." << to.port;
  EXPECT_EQ(made->from, from);
}

}  // namespace

// From an empty graph to a clone, with the mouse: nodes from the palette, ports connected by
// dragging, then both canvases placed and a region painted in the viewports.
TEST(StudioWindow, BuildsACloneGraphWithTheMouseAndPaintsIt) {
  const auto dir = test::tempDir("studio-build");
  StudioWindow window(test::registry());
  window.resize(1600, 1000);
  window.setOutputDir(dir);
  window.show();
  window.activateWindow();
  ASSERT_TRUE(QTest::qWaitForWindowActive(&window));
  QTest::keyClick(&window, Qt::Key_N, Qt::ControlModifier);
  ASSERT_TRUE(window.document().graph().nodes.empty());

  // The first node by a double click on its palette entry.
  auto* palette = window.findChild<QTreeWidget*>();
  ASSERT_NE(palette, nullptr);
  QTreeWidgetItem* loadEntry = nullptr;
  for (int g = 0; g < palette->topLevelItemCount(); ++g)
    for (int i = 0; i < palette->topLevelItem(g)->childCount(); ++i)
      if (palette->topLevelItem(g)->child(i)->data(0, Qt::UserRole).toString() ==
          "geobrush.load_mesh")
        loadEntry = palette->topLevelItem(g)->child(i);
  ASSERT_NE(loadEntry, nullptr);
  palette->scrollToItem(loadEntry);
  const QPoint entry = palette->visualItemRect(loadEntry).center();
  QTest::mouseClick(palette->viewport(), Qt::LeftButton, {}, entry);
  QTest::mouseDClick(palette->viewport(), Qt::LeftButton, {}, entry);
  ASSERT_EQ(window.document().graph().nodes.size(), 1u);
  const std::string sourceMesh = window.document().graph().nodes.begin()->first;
  const std::string canvas = addNode(window, "geobrush.canvas_grow");
  const std::string sourceMap = addNode(window, "geobrush.gdem");
  const std::string targetMesh = addNode(window, "geobrush.primitive");
  const std::string targetMap = addNode(window, "geobrush.dem");
  const std::string strokes = addNode(window, "geobrush.strokes");
  const std::string roi = addNode(window, "geobrush.roi");
  const std::string membrane = addNode(window, "geobrush.membrane");
  const std::string stitch = addNode(window, "geobrush.stitch");
  EXPECT_EQ(window.document().graph().nodes.size(), 9u);
  ASSERT_EQ(window.setParam(sourceMesh, "path", (test::meshPath("mountain.obj")).string()), "");
  ASSERT_EQ(window.setParam(targetMap, "scale", 0.05), "");

  const std::vector<std::pair<Endpoint, Endpoint>> wires = {
      {{sourceMesh, "mesh"}, {canvas, "mesh"}},
      {{canvas, "canvas"}, {sourceMap, "canvas"}},
      {{targetMesh, "mesh"}, {targetMap, "mesh"}},
      {{sourceMap, "parameterization"}, {targetMap, "source"}},
      {{strokes, "strokes"}, {roi, "strokes"}},
      {{sourceMap, "parameterization"}, {roi, "source"}},
      {{targetMap, "parameterization"}, {roi, "target"}},
      {{roi, "region"}, {membrane, "region"}},
      {{sourceMap, "parameterization"}, {membrane, "source"}},
      {{targetMap, "parameterization"}, {membrane, "target"}},
      {{roi, "region"}, {stitch, "region"}},
      {{sourceMap, "parameterization"}, {stitch, "source"}},
      {{targetMap, "parameterization"}, {stitch, "target"}},
      {{membrane, "offset"}, {stitch, "offset"}}};
  for (const auto& [from, to] : wires)
    connectByMouse(window, from, to);
  EXPECT_EQ(window.document().graph().connections.size(), wires.size());
  ASSERT_TRUE(waitUntilIdle(window));

  // The clone is recognised; nothing is painted yet, so the canvas cannot grow.
  auto& panel = window.clonePanel();
  ASSERT_TRUE(panel.roles().found());
  EXPECT_EQ(panel.roles().paste, stitch);
  EXPECT_FALSE(window.lastReport().ok);
  EXPECT_NE(window.lastReport().error.find(canvas), std::string::npos);
  Viewport& source = panel.sourceView();
  ASSERT_TRUE(source.surface().mesh);

  // The mountain's peak as the source origin, a canvas painted around it.
  const Eigen::Vector3d peak(0.068548, 19.73209, 0.029055);
  panel.setTool(CloneTool::SourceOrigin);
  QTest::mouseClick(&source, Qt::LeftButton, {}, onScreen(source, peak));
  panel.setTool(CloneTool::PaintCanvas);
  panel.setBrushRadius(8);
  const QPoint peakPixel = onScreen(source, vec3Of(window.document(), canvas, "origin"));
  drag(&source, peakPixel, peakPixel + QPoint(2, 2), {}, 2);
  ASSERT_TRUE(waitUntilIdle(window));
  // Now the target canvas is what fails: its origin is not on the sphere yet.
  EXPECT_NE(window.lastReport().error.find(targetMap), std::string::npos)
      << window.lastReport().error;
  Viewport& target = panel.targetView();
  ASSERT_TRUE(target.surface().mesh);

  panel.setTool(CloneTool::TargetOrigin);
  QTest::mouseClick(&target, Qt::LeftButton, {}, onScreen(target, {0, 0, 1}));
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  const auto targetVertices = target.surface().mesh->surface.n_vertices();

  panel.setTool(CloneTool::PaintRegion);
  panel.setBrushRadius(6);
  const QPoint middle = onScreen(target, vec3Of(window.document(), targetMap, "origin"));
  drag(&target, middle, middle + QPoint(3, 0), {}, 2);
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  const auto result =
      std::dynamic_pointer_cast<const Mesh>(window.evaluator().output(stitch, "mesh"));
  ASSERT_TRUE(result);
  EXPECT_GT(result->surface.n_vertices(), targetVertices);
  QTest::mouseMove(&target, middle);
  screenshot(window, "studio_built.png");
  ASSERT_TRUE(window.saveFile(QString::fromStdString((dir / "built.json").string())));
  EXPECT_EQ(readGraphFile(dir / "built.json").connections.size(), wires.size());
}

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  QApplication app(argc, argv);
  // The suite closes windows and goes on.
  app.setQuitOnLastWindowClosed(false);
  return RUN_ALL_TESTS();
}

// The EMD comparison graph: the source can be coloured by its modes and the target by the
// transferred signal, each with its legend; back to the canvas colours on asking.
TEST(StudioWindow, ColoursTheSurfacesByTheFieldsTheGraphComputed) {
  const auto dir = test::tempDir("studio-fields");
  StudioWindow window(test::registry());
  window.setOutputDir(dir);
  ASSERT_TRUE(window.openFile(
      QString::fromStdString(graphFile("compare_mountain_sphere_emd.json").string())));
  window.resize(1200, 700);
  window.show();
  ASSERT_TRUE(QTest::qWaitForWindowExposed(&window));
  ASSERT_TRUE(waitUntilIdle(window));
  ASSERT_TRUE(window.lastReport().ok) << window.lastReport().error;
  auto& panel = window.clonePanel();
  // EMD's paste (the belt at the end of its chain) is the target view's result.
  EXPECT_EQ(panel.roles().paste, "belt");
  ASSERT_TRUE(panel.liveView().values.result);
  EXPECT_FALSE(panel.colourTargetBy("source_modes.modes: h1"));  // another mesh's field
  ASSERT_TRUE(panel.colourSourceBy("source_modes.modes: h1"));
  ASSERT_TRUE(panel.colourTargetBy("transfer.signal: detail"));
  ASSERT_TRUE(panel.targetView().legend());
  EXPECT_EQ(panel.targetView().legend()->name, "detail");
  EXPECT_TRUE(panel.targetView().legend()->range.diverging);
  QTest::qWait(50);
  const QImage source = panel.sourceView().grab().toImage();
  int red = 0, blue = 0;
  for (int y = 0; y < source.height(); ++y)
    for (int x = 0; x < source.width(); ++x) {
      const QColor c = source.pixelColor(x, y);
      red += c.red() > c.blue() + 60;
      blue += c.blue() > c.red() + 60;
    }
  EXPECT_GT(red, 50);
  EXPECT_GT(blue, 50);
  screenshot(window, "studio_fields.png");
  ASSERT_TRUE(panel.colourTargetBy(""));
  EXPECT_FALSE(panel.targetView().legend());
}
