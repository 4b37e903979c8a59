// The studio's frame time on the live-brush scene (the GeoBrush template, a 164k-vertex sphere
// target): the target view redrawn as it orbits (render and overlays), and one step of a target
// drag (the edit, its live evaluation, the redraw). Needs a display: xvfb-run -a studio_bench.
#include <benchmark/benchmark.h>

#include <QApplication>
#include <QMouseEvent>
#include <chrono>
#include <cmath>
#include <thread>

#include "graph_edits.hpp"
#include "studio_window.hpp"

namespace {

using namespace geobrush;
using studio::StudioWindow;

// Runs the window's events until its evaluations have ended.
void waitUntilIdle(StudioWindow& window) {
  do {
    QCoreApplication::processEvents(QEventLoop::AllEvents, 5);
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  } while (!window.idle());
  QCoreApplication::processEvents();
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

// Each step moves the target canvas's origin along the sphere, as a drag does.
void BM_StudioTargetDragStep(benchmark::State& state) {
  StudioWindow& window = sceneWindow();
  if (!window.lastReport().ok) return state.SkipWithError(window.lastReport().error.c_str());
  const std::string node = window.clonePanel().roles().targetMap;
  auto& target = window.clonePanel().targetView();
  int step = 0;
  for (auto _ : state) {
    const double angle = 0.01 * (step++ % 20);
    window.setParam(node, "origin", Vec3{std::sin(angle), 0, std::cos(angle)});
    waitUntilIdle(window);
    target.repaint();
  }
  if (!window.lastReport().ok) state.SkipWithError(window.lastReport().error.c_str());
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
