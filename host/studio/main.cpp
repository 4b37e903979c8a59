// geobrush-studio [GRAPH] [--out DIR] [--screenshot PNG]: the interactive host. With --screenshot
// it opens the graph, evaluates it, writes a picture of the whole window and exits (for docs and
// tests); without a graph, a picture of the empty window.
#include <QApplication>
#include <QCommandLineParser>
#include <QEventLoop>
#include <QTimer>
#include <cstdio>
#include <filesystem>
#include <system_error>

#include "geobrush/memory.hpp"
#include "studio_window.hpp"

int main(int argc, char** argv) {
  geobrush::reuseFreedMemory();
  QApplication app(argc, argv);
  QApplication::setApplicationName("geobrush-studio");
  QCommandLineParser parser;
  parser.setApplicationDescription("GeoBrush Studio: wire clone graphs and evaluate them.");
  parser.addHelpOption();
  parser.addPositionalArgument("graph", "Graph file (.json) to open.");
  QCommandLineOption screenshot(
      "screenshot", "Evaluate the graph, write a screenshot of the window, exit.", "png");
  parser.addOption(screenshot);
  QCommandLineOption out("out", "Folder for the graph's output files (default: the graph's).",
                         "dir");
  parser.addOption(out);
  parser.process(app);

  geobrush::NodeRegistry registry;
  for (const auto& error : registry.loadPlugins(geobrush::defaultPluginDirs()).errors)
    std::fprintf(stderr, "warning: %s\n", error.c_str());
  geobrush::studio::StudioWindow window(registry);
  if (parser.isSet(out)) {
    // As `geobrush run --out` does: the folder is made where it is missing.
    const std::filesystem::path dir = parser.value(out).toStdString();
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
      std::fprintf(stderr, "error: %s: cannot create the output folder: %s\n", dir.c_str(),
                   ec.message().c_str());
      return 2;
    }
    window.setOutputDir(dir);
  }
  const QStringList args = parser.positionalArguments();
  const bool opened = !args.isEmpty() && window.openFile(args.front());
  if (!parser.isSet(screenshot)) {
    window.show();
    return app.exec();
  }
  if (!args.isEmpty() && !opened) {
    std::fprintf(stderr, "error: %s: the graph could not be opened (see the log)\n",
                 args.front().toLocal8Bit().constData());
    return 2;
  }
  window.show();
  bool ok = true;
  // Without a graph: the empty window.
  if (opened && window.document().evaluable()) {
    // The whole graph, files written, then whatever follows it (a settling pass) to its end.
    QEventLoop loop;
    QObject::connect(&window, &geobrush::studio::StudioWindow::becameIdle, &loop,
                     [&] { loop.quit(); });
    QTimer::singleShot(0, &window, [&] { window.evaluate(); });
    loop.exec();
    ok = window.lastReport().ok;
  }
  QApplication::processEvents();
  const QString png = parser.value(screenshot);
  if (!window.grab().save(png, "PNG")) {
    std::fprintf(stderr, "error: %s: cannot write the screenshot\n", png.toLocal8Bit().constData());
    return 1;
  }
  if (!ok) {
    std::fprintf(stderr, "error: %s\n", window.lastReport().error.c_str());
    return 1;
  }
  return 0;
}
