// The studio's frame time on the live-brush scene (the GeoBrush template, a 164k-vertex sphere
// target): the target view redrawn as it orbits (render and overlays), and one step of a target
// drag (the edit, its live evaluation, the redraw). Needs a display: xvfb-run -a studio_bench.
#include <benchmark/benchmark.h>

#include <QApplication>
#include <QMouseEvent>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>
#include <vector>

#include "graph_edits.hpp"
#include "studio_window.hpp"

namespace {

using namespace geobrush;
using studio::StudioWindow;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

// Runs the window's events until its evaluations have ended. Returns the longest the UI thread
// was busy in one go (a call that found events handles all that were pending): while it is
// busy, no frame can be drawn.
double waitUntilIdle(StudioWindow& window) {
  double longest = 0;
  const auto handleEvents = [&](int maxMilliseconds) {
    const auto start = std::chrono::steady_clock::now();
    QCoreApplication::processEvents(QEventLoop::AllEvents, maxMilliseconds);
    longest = std::max(longest, millisecondsSince(start));
  };
  do {
    handleEvents(5);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  } while (!window.idle());
  handleEvents(0);
  return longest;
}

double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  return values[values.size() / 2];
}

// The scene open, evaluated and shown at a studio's size; shared by the benchmarks.
StudioWindow& sceneWindow() {
  static StudioWindow* window = [] {
    Graph graph = bench::proceduralClone("geobrush", 128, 0.15, 1.0);
    const auto file = test::tempDir("studio-bench") / "scene.json";
    writeGraphFile(graph, file);
    auto* opened = new StudioWindow(test::registry());
    opened->resize(1400, 900);
    opened->show();
    opened->openFile(QString::fromStdString(file.string()));
    waitUntilIdle(*opened);
    return opened;
  }();
  return *window;
}

// A right-button drag of one pixel: the view orbits and is drawn again.
void orbitOnePixel(QWidget& view, int step) {
  const QPointF from(200 + step % 2, 200), to(201 - step % 2, 200);
  QMouseEvent press(QEvent::MouseButtonPress, from, view.mapToGlobal(from), Qt::RightButton,
                    Qt::RightButton, {});
  QApplication::sendEvent(&view, &press);
  QMouseEvent move(QEvent::MouseMove, to, view.mapToGlobal(to), Qt::NoButton, Qt::RightButton, {});
  QApplication::sendEvent(&view, &move);
  QMouseEvent release(QEvent::MouseButtonRelease, to, view.mapToGlobal(to), Qt::RightButton,
                      Qt::NoButton, {});
  QApplication::sendEvent(&view, &release);
  view.repaint();
}

void BM_StudioOrbitRedraw(benchmark::State& state) {
  StudioWindow& window = sceneWindow();
  if (!window.lastReport().ok) return state.SkipWithError(window.lastReport().error.c_str());
  auto& target = window.clonePanel().targetView();
  state.counters["target_vertices"] = double(target.surface().mesh->surface.n_vertices());
  int step = 0;
  for (auto _ : state)
    orbitOnePixel(target, step++);
}

// Each step moves the target canvas's origin along the sphere, as a drag does: the time is the
// step's, from the edit to the new paste drawn. The evaluation runs on its own thread; the UI
// thread stays free to draw except while it shows the new result. Counters, per step: the
// longest the UI thread was busy in one go (a frame's time while dragging: the view redraws at
// least 1000 / frame_ms times a second), median and largest.
void BM_StudioTargetDragStep(benchmark::State& state) {
  StudioWindow& window = sceneWindow();
  if (!window.lastReport().ok) return state.SkipWithError(window.lastReport().error.c_str());
  const std::string node = window.clonePanel().roles().targetMap;
  auto& target = window.clonePanel().targetView();
  int step = 0;
  std::vector<double> frameMs;
  for (auto _ : state) {
    const double angle = 0.01 * (step++ % 20);
    window.setParam(node, "origin", Vec3{std::sin(angle), 0, std::cos(angle)});
    double longest = waitUntilIdle(window);
    const auto start = std::chrono::steady_clock::now();
    target.repaint();
    longest = std::max(longest, millisecondsSince(start));
    frameMs.push_back(longest);
  }
  if (!window.lastReport().ok) return state.SkipWithError(window.lastReport().error.c_str());
  state.counters["frame_ms"] = median(frameMs);
  state.counters["frame_max_ms"] = *std::max_element(frameMs.begin(), frameMs.end());
}

BENCHMARK(BM_StudioOrbitRedraw)->Unit(benchmark::kMillisecond)->MinTime(2.0);
BENCHMARK(BM_StudioTargetDragStep)->Unit(benchmark::kMillisecond)->MinTime(2.0);

}  // namespace

int main(int argc, char** argv) {
  QApplication app(argc, argv);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
