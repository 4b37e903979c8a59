// The studio's main window: the palette of every loaded node type (from the plugins), the node
// editor, and a log; graphs open and save in the CLI's format, and evaluate on a worker thread
// with the same evaluator as `geobrush run`, so the window never blocks.
#pragma once

#include <QMainWindow>
#include <atomic>
#include <memory>
#include <thread>

#include "node_editor.hpp"
#include "param_panel.hpp"
#include "studio_document.hpp"

class QPlainTextEdit;
class QAction;
class QTreeWidget;

namespace geobrush::studio {

class StudioWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit StudioWindow(const NodeRegistry& registry, QWidget* parent = nullptr);
  ~StudioWindow() override;

  // Opens a graph file; errors go to the log and the status bar. Returns whether it opened.
  bool openFile(const QString& path);
  bool saveFile(const QString& path);
  // Adds a node of the type at the middle of the editor (what a double click in the palette
  // does); returns the error or an empty string.
  std::string addNode(const std::string& typeId);
  StudioDocument& document() { return document_; }
  NodeEditor& editor() { return *editor_; }
  // Starts an evaluation of the open graph on the worker thread (cancelling one under way);
  // `evaluated` is emitted when it ends.
  void evaluate();
  // Where the graph's output files go; empty (the default): the graph file's folder, as for
  // `geobrush run` without --out.
  void setOutputDir(const std::filesystem::path& dir) { outputDir_ = dir; }
  bool evaluating() const { return worker_.joinable() && !finished_; }
  const StudioDocument& document() const { return document_; }
  const EvalReport& lastReport() const { return report_; }

 signals:
  void evaluated(bool ok);

 private:
  void log(const QString& line);
  // Applies the outcome of a document edit: the error to the log and status bar, or the new
  // graph to the editor (after the current event, which may come from an item being replaced).
  void edited(const std::string& error);
  void undoRedo(bool undo);
  void refresh(const EvalReport* report);
  void finishEvaluation(int generation, EvalReport report);
  void stopWorker();

  const NodeRegistry& registry_;
  StudioDocument document_;
  NodeEditor* editor_;
  QTreeWidget* palette_;
  QPlainTextEdit* log_;
  ParamPanel* params_;
  QAction* undoAction_;
  QAction* redoAction_;
  std::string selected_;
  EvalReport report_;
  std::unique_ptr<Evaluator> evaluator_;
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  bool finished_ = true;
  std::filesystem::path outputDir_;
  // Counts evaluations: a result that arrives after a newer one started, or after the graph was
  // replaced, is dropped.
  int generation_ = 0;
};

}  // namespace geobrush::studio
