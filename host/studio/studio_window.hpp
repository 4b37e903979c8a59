// The studio's main window: the source and target viewports with the brush tools, the palette of
// every loaded node type (from the plugins), the node editor, and a log; graphs open and save in
// the CLI's format, and evaluate on a worker thread with the same evaluator as `geobrush run`,
// so the window never blocks. Each edit re-evaluates what the viewports show; once the edits
// stop, a settling evaluation replaces warm-started results by what `geobrush run` computes.
#pragma once

#include <QMainWindow>
#include <atomic>
#include <functional>
#include <memory>
#include <set>
#include <thread>

#include "clone_panel.hpp"
#include "node_editor.hpp"
#include "output_view.hpp"
#include "param_panel.hpp"
#include "studio_document.hpp"

class QPlainTextEdit;
class QAction;
class QProgressBar;
class QTreeWidget;

namespace geobrush::studio {

class StudioWindow : public QMainWindow {
  Q_OBJECT

 public:
  explicit StudioWindow(const NodeRegistry& registry, QWidget* parent = nullptr);
  ~StudioWindow() override;

  // Starts an empty, untitled graph.
  void newFile();
  // Opens a graph file; errors go to the log and the status bar. Returns whether it opened.
  bool openFile(const QString& path);
  bool saveFile(const QString& path);
  // Saves to the graph's file (asking where for an untitled graph); false if nothing was saved.
  bool save();

  // Where the graph has unsaved changes (the title's marker), asks whether to save them, as
  // closing, New and Open do; false when the user cancels or the save fails.
  bool keepOrDropChanges();
  enum class UnsavedChoice { Save, Discard, Cancel };
  // The question keepOrDropChanges() asks; a dialog where unset (tests answer it themselves).
  std::function<UnsavedChoice()> askAboutChanges;
  // Adds a node of the type at the middle of the editor (what a double click in the palette
  // does); returns the error or an empty string.
  std::string addNode(const std::string& typeId);
  // A param edit, as the parameter panel makes it; returns the error or an empty string.
  std::string setParam(const std::string& node, const std::string& param, const ParamValue& value);
  StudioDocument& document() { return document_; }
  NodeEditor& editor() { return *editor_; }
  ClonePanel& clonePanel() { return *clone_; }
  // What a graph without a clone shows: a node's mesh output.
  OutputView& outputView() { return *output_; }
  // Selects the node as a click in the node editor does: its params, its clone or its mesh.
  void selectNode(const std::string& node);
  // Starts an evaluation of the whole graph on the worker thread (cancelling one under way),
  // writing the graph's files; `evaluated` is emitted when it ends.
  void evaluate();
  // Evaluates what the viewports show (after the one under way, if any); what edits call.
  void evaluateLive();
  // Nothing evaluating and nothing waiting to be.
  bool idle() const { return !evaluating() && !pendingLive_; }
  // Where the graph's output files go; empty (the default): the graph file's folder, as for
  // `geobrush run` without --out.
  void setOutputDir(const std::filesystem::path& dir) { outputDir_ = dir; }
  bool evaluating() const { return worker_.joinable() && !finished_; }
  const StudioDocument& document() const { return document_; }
  const EvalReport& lastReport() const { return report_; }
  // What the log shows: the open graph's messages (opening another graph clears it).
  QString logText() const;
  // The evaluator of the open graph (read it only while idle()).
  const Evaluator& evaluator() const { return *evaluator_; }

 signals:
  void evaluated(bool ok);
  // Emitted when the evaluations that edits started have all ended (see idle()).
  void becameIdle();

 protected:
  void closeEvent(QCloseEvent* event) override;

 private:
  UnsavedChoice askWithDialog();
  // The graph's file (or "untitled") in the title, with the place of the modified mark.
  void showTitle(const QString& name);
  void log(const QString& line);
  // Applies the outcome of a document edit: the error to the log and status bar, or the new
  // graph to the editor (after the current event, which may come from an item being replaced).
  void edited(const std::string& error);
  void undoRedo(bool undo);
  // The Undo and Redo commands enabled and named by what they would change; the title marked
  // where the graph has unsaved changes.
  void updateUndoActions();
  void refresh(const EvalReport* report);
  // Full: every node, settled, files written (F5). Live: what the viewports show, warm. Settle:
  // the same, recomputing what a warm start gave.
  enum class EvalMode { Full, Live, Settle };
  void startEvaluation(EvalMode mode);
  void finishEvaluation(int generation, EvalMode mode, EvalReport report, LiveViewPtr view);
  void showProgress(const std::string& node, double fraction);
  void stopWorker();
  void updateRoles();
  // The selected node's mesh, or the graph's result, in the output view (graphs without a clone).
  void showOutput();
  // Forgets everything of the graph shown before (a new or opened document).
  void startOver();

  const NodeRegistry& registry_;
  StudioDocument document_;
  NodeEditor* editor_;
  QTreeWidget* palette_;
  QPlainTextEdit* log_;
  ParamPanel* params_;
  ClonePanel* clone_;
  OutputView* output_;
  QProgressBar* progress_;
  QAction* undoAction_;
  QAction* redoAction_;
  std::string selected_;
  EvalReport report_;
  std::unique_ptr<Evaluator> evaluator_;
  std::thread worker_;
  std::atomic<bool> cancel_{false};
  bool finished_ = true;
  bool pendingLive_ = false;
  bool radiusChosen_ = false;
  int computedSinceEdit_ = 0;  // nodes the evaluations since the last edit computed
  std::string lastLiveError_;
  std::set<std::string> lastLiveWarnings_;  // as the log lines say them
  std::filesystem::path outputDir_;
  // Counts evaluations: a result that arrives after a newer one started, or after the graph was
  // replaced, is dropped.
  int generation_ = 0;
};

}  // namespace geobrush::studio
