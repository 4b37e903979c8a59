#include "studio_window.hpp"

#include "clone_edits.hpp"

#include <QAction>
#include <QCloseEvent>
#include <QDockWidget>
#include <QFileDialog>
#include <QMenuBar>
#include <QMessageBox>
#include <QPlainTextEdit>
#include <QProgressBar>
#include <QSplitter>
#include <QStatusBar>
#include <QTimer>
#include <QToolBar>
#include <QTreeWidget>
#include <cmath>
#include <map>
#include <set>

namespace geobrush::studio {

StudioWindow::StudioWindow(const NodeRegistry& registry, QWidget* parent)
    : QMainWindow(parent),
      registry_(registry),
      document_(registry),
      editor_(new NodeEditor(registry, this)),
      palette_(new QTreeWidget(this)),
      log_(new QPlainTextEdit(this)),
      params_(new ParamPanel(registry, this)),
      clone_(new ClonePanel(document_, this)),
      output_(new OutputView(document_, this)),
      progress_(new QProgressBar(this)),
      evaluator_(std::make_unique<Evaluator>(registry)) {
  setWindowTitle("GeoBrush Studio");
  resize(1400, 900);
  auto* central = new QSplitter(Qt::Vertical, this);
  central->addWidget(clone_);
  central->addWidget(output_);
  central->addWidget(editor_);
  central->setSizes({520, 520, 300});
  setCentralWidget(central);
  addToolBar(clone_->toolBar());
  clone_->onEdited = [this](const std::string& error) { edited(error); };
  output_->onEdited = [this](const std::string& error) { edited(error); };
  clone_->onMessage = [this](const QString& text) { statusBar()->showMessage(text, 4000); };
  progress_->setMaximumWidth(240);
  progress_->setRange(0, 100);
  progress_->hide();
  statusBar()->addPermanentWidget(progress_);

  // The palette lists the types the plugins declared, by category.
  palette_->setHeaderLabel("Nodes");
  std::map<std::string, QTreeWidgetItem*> categories;
  for (const NodeType* type : registry.types()) {
    const std::string category = type->category.empty() ? "Other" : type->category;
    QTreeWidgetItem*& group = categories[category];
    if (!group) group = new QTreeWidgetItem(palette_, {QString::fromStdString(category)});
    auto* item = new QTreeWidgetItem(
        group, {QString::fromStdString(type->label.empty() ? type->id : type->label)});
    item->setToolTip(0, QString::fromStdString(type->id + "\n" + type->doc));
    item->setData(0, Qt::UserRole, QString::fromStdString(type->id));
  }
  palette_->expandAll();
  connect(palette_, &QTreeWidget::itemDoubleClicked, this, [this](QTreeWidgetItem* item) {
    const QString id = item->data(0, Qt::UserRole).toString();
    if (!id.isEmpty()) addNode(id.toStdString());
  });
  params_->setMinimumWidth(280);
  auto* paramsDock = new QDockWidget("Parameters", this);
  paramsDock->setWidget(params_);
  addDockWidget(Qt::RightDockWidgetArea, paramsDock);
  params_->onChange = [this](const std::string& node, const std::string& param,
                             const ParamValue& value) { setParam(node, param, value); };
  editor_->onConnect = [this](const Endpoint& from, const Endpoint& to) {
    edited(document_.connect(from, to));
  };
  editor_->onDelete = [this](const std::vector<std::string>& nodes) {
    edited(document_.removeNodes(nodes));
  };
  editor_->onMoved = [this](const std::string& node, double x, double y) {
    document_.moveNode(node, x, y);
    updateUndoActions();
  };
  editor_->onSelected = [this](const std::string& node) { selectNode(node); };
  auto* paletteDock = new QDockWidget("Palette", this);
  paletteDock->setWidget(palette_);
  addDockWidget(Qt::LeftDockWidgetArea, paletteDock);
  log_->setReadOnly(true);
  auto* logDock = new QDockWidget("Log", this);
  logDock->setWidget(log_);
  addDockWidget(Qt::BottomDockWidgetArea, logDock);
  resizeDocks({logDock}, {110}, Qt::Vertical);

  QMenu* file = menuBar()->addMenu("&File");
  file->addAction("&New", QKeySequence::New, [this] {
    if (keepOrDropChanges()) newFile();
  });
  file->addAction("&Open...", QKeySequence::Open, [this] {
    if (!keepOrDropChanges()) return;
    const QString path = QFileDialog::getOpenFileName(this, "Open graph", {}, "Graphs (*.json)");
    if (!path.isEmpty()) openFile(path);
  });
  file->addAction("&Save", QKeySequence::Save, [this] { save(); });
  file->addAction("Save &As...", QKeySequence::SaveAs, [this] {
    const QString path = QFileDialog::getSaveFileName(this, "Save graph", {}, "Graphs (*.json)");
    if (!path.isEmpty()) saveFile(path);
  });
  file->addSeparator();
  file->addAction("&Quit", QKeySequence::Quit, [this] { close(); });
  QMenu* edit = menuBar()->addMenu("&Edit");
  undoAction_ = edit->addAction("&Undo", QKeySequence::Undo, [this] { undoRedo(true); });
  redoAction_ = edit->addAction("&Redo", QKeySequence::Redo, [this] { undoRedo(false); });
  undoAction_->setEnabled(false);
  redoAction_->setEnabled(false);
  QMenu* graph = menuBar()->addMenu("&Graph");
  graph->addAction("&Evaluate", QKeySequence(Qt::Key_F5), [this] { evaluate(); });
  graph->addAction("&Frame graph", QKeySequence(Qt::SHIFT | Qt::Key_Home),
                   [this] { editor_->frameGraph(); });
  statusBar()->showMessage("Open a graph (File > Open)");
}

StudioWindow::~StudioWindow() {
  stopWorker();
}

bool StudioWindow::openFile(const QString& path) {
  stopWorker();
  const std::string error = document_.open(path.toStdString());
  if (!error.empty()) {
    log("error: " + QString::fromStdString(error));
    statusBar()->showMessage(QString::fromStdString(error));
    return false;
  }
  startOver();
  log_->clear();
  for (const auto& name : document_.missingNodes())
    log("warning: " + path + ": node '" + QString::fromStdString(name) +
        "': no loaded plugin provides '" +
        QString::fromStdString(document_.graph().nodes.at(name).type) + "'");
  showTitle(path);
  refresh(nullptr);
  statusBar()->showMessage("Opened " + path);
  evaluateLive();
  return true;
}

void StudioWindow::startOver() {
  evaluator_ = std::make_unique<Evaluator>(registry_);
  report_ = {};
  selected_.clear();
  pendingLive_ = false;
  radiusChosen_ = false;
  computedSinceEdit_ = 0;
  lastLiveError_.clear();
  lastLiveWarnings_.clear();
  clone_->clear();
  output_->showNothing();
  updateRoles();
  params_->showNode(document_, selected_);
  updateUndoActions();
}

void StudioWindow::newFile() {
  stopWorker();
  document_.newGraph();
  startOver();
  showTitle("untitled");
  refresh(nullptr);
  statusBar()->showMessage("New graph: double-click node types in the palette to add them");
}

bool StudioWindow::saveFile(const QString& path) {
  editor_->storePositions(document_.graph());
  const std::string error = document_.save(path.toStdString());
  if (!error.empty()) {
    log("error: " + QString::fromStdString(error));
    return false;
  }
  showTitle(path);
  updateUndoActions();
  statusBar()->showMessage("Saved " + path);
  return true;
}

void StudioWindow::showTitle(const QString& name) {
  // [*]: where Qt shows the modified mark (updateUndoActions).
  setWindowTitle("GeoBrush Studio - " + name + "[*]");
}

bool StudioWindow::save() {
  QString path = QString::fromStdString(document_.path().string());
  if (path.isEmpty())
    path = QFileDialog::getSaveFileName(this, "Save graph", {}, "Graphs (*.json)");
  return !path.isEmpty() && saveFile(path);
}

bool StudioWindow::keepOrDropChanges() {
  if (!document_.modified()) return true;
  switch (askAboutChanges ? askAboutChanges() : askWithDialog()) {
    case UnsavedChoice::Save:
      return save();
    case UnsavedChoice::Discard:
      return true;
    case UnsavedChoice::Cancel:
      return false;
  }
  return false;
}

StudioWindow::UnsavedChoice StudioWindow::askWithDialog() {
  const QString name = document_.path().empty()
                           ? QString("the untitled graph")
                           : QString::fromStdString(document_.path().filename().string());
  const auto answer = QMessageBox::question(
      this, "Unsaved changes", "Save the changes to " + name + "?",
      QMessageBox::Save | QMessageBox::Discard | QMessageBox::Cancel, QMessageBox::Save);
  if (answer == QMessageBox::Save) return UnsavedChoice::Save;
  return answer == QMessageBox::Discard ? UnsavedChoice::Discard : UnsavedChoice::Cancel;
}

void StudioWindow::closeEvent(QCloseEvent* event) {
  if (!keepOrDropChanges()) {
    event->ignore();
    return;
  }
  stopWorker();
  event->accept();
}

void StudioWindow::evaluate() {
  pendingLive_ = false;
  startEvaluation(EvalMode::Full);
}

void StudioWindow::evaluateLive() {
  // A clone's views, or the mesh the output view shows, follow each edit.
  if ((!clone_->roles().found() && !output_->shown()) || !document_.evaluable()) return;
  if (evaluating()) {
    pendingLive_ = true;
    return;
  }
  startEvaluation(EvalMode::Live);
}

void StudioWindow::selectNode(const std::string& node) {
  if (!node.empty() && editor_->selectedNodes() != std::vector<std::string>{node})
    editor_->focusNode(node);
  selected_ = node;
  params_->showNode(document_, node);
  // Selecting another clone's ROI (or strokes) node shows that clone.
  const auto it = document_.graph().nodes.find(node);
  if (it != document_.graph().nodes.end() && isRoiType(it->second.type)) {
    updateRoles();
    evaluateLive();
  }
  if (!clone_->roles().found() && idle()) showOutput();
}

void StudioWindow::showOutput() {
  const auto output = outputToShow(document_.graph(), registry_, *evaluator_, selected_);
  const ValuePtr value = output ? evaluator_->output(output->node, output->port) : nullptr;
  if (auto image = std::dynamic_pointer_cast<const Image>(value))
    output_->showImage(*output, std::move(image));
  else if (auto mesh = std::dynamic_pointer_cast<const Mesh>(value))
    output_->showMesh(*output, std::move(mesh));
  else
    output_->showNothing();
}

void StudioWindow::updateRoles() {
  const auto it = document_.graph().nodes.find(selected_);
  const bool roi = it != document_.graph().nodes.end() && isRoiType(it->second.type);
  const std::string preferred = roi ? selected_ : clone_->roles().roi;
  clone_->setRoles(findClone(document_.graph(), preferred));
  // A graph without a clone shows a node's mesh instead.
  clone_->setVisible(clone_->roles().found());
  output_->setVisible(!clone_->roles().found());
  clone_->toolBar()->setEnabled(clone_->roles().found());
}

void StudioWindow::startEvaluation(EvalMode mode) {
  stopWorker();
  if (!document_.evaluable()) {
    log("error: the graph has nodes whose plugin is missing: it cannot be evaluated");
    emit evaluated(false);
    emit becameIdle();
    return;
  }
  Graph graph = document_.graph();
  try {
    prepareGraph(graph, registry_);
  } catch (const GraphError& e) {
    // A graph being wired is often incomplete: the live view waits quietly for the next edit.
    if (mode == EvalMode::Full) log("error: " + QString::fromStdString(e.what()));
    statusBar()->showMessage(QString::fromStdString(e.what()));
    emit evaluated(false);
    emit becameIdle();
    return;
  }
  cancel_ = false;
  finished_ = false;
  statusBar()->showMessage(mode == EvalMode::Full ? "Evaluating..." : "Updating the clone...");
  const int generation = ++generation_;
  EvalOptions options;
  options.cancel = &cancel_;
  options.outputDir = outputDir_;
  options.settle = mode != EvalMode::Live;
  if (mode != EvalMode::Full && clone_->roles().found())
    options.targets = clone_->roles().liveTargets();
  else if (mode != EvalMode::Full && output_->shown())
    options.targets = {output_->shown()->node};
  options.progress = [this, generation](const std::string& node, double fraction) {
    QMetaObject::invokeMethod(
        this,
        [this, generation, node, fraction] {
          if (generation == generation_) showProgress(node, fraction);
        },
        Qt::QueuedConnection);
  };
  worker_ =
      std::thread([this, generation, mode, roles = clone_->roles(), basis = clone_->viewBasis(),
                   options = std::move(options), graph = std::move(graph)] {
        EvalReport report = evaluator_->evaluate(graph, options);
        LiveViewPtr view;
        if (roles.found() && !report.cancelled)
          view = std::make_shared<const LiveView>(
              makeLiveView(*evaluator_, roles, graph, registry_, basis));
        QMetaObject::invokeMethod(
            this,
            [this, generation, mode, report = std::move(report), view = std::move(view)]() mutable {
              finishEvaluation(generation, mode, std::move(report), std::move(view));
            },
            Qt::QueuedConnection);
      });
}

void StudioWindow::showProgress(const std::string& node, double fraction) {
  progress_->show();
  progress_->setValue(int(std::lround(100 * fraction)));
  progress_->setFormat(QString::fromStdString(node) + " %p%");
}

void StudioWindow::finishEvaluation(int generation, EvalMode mode, EvalReport report,
                                    LiveViewPtr view) {
  if (generation != generation_) return;
  finished_ = true;
  if (worker_.joinable()) worker_.join();
  progress_->hide();
  report_ = std::move(report);
  // A live evaluation runs on every dab: the log gets a warning or an error when it appears, not
  // again while it stays.
  std::set<std::string> warnings;
  for (const auto& run : report_.runs)
    for (const auto& warning : run.warnings)
      warnings.insert("warning: node '" + run.node + "': " + warning);
  const bool live = mode != EvalMode::Full;
  for (const std::string& warning : warnings)
    if (!live || !lastLiveWarnings_.count(warning)) log(QString::fromStdString(warning));
  if (!report_.ok && (!live || report_.error != lastLiveError_))
    log("error: " + QString::fromStdString(report_.error));
  if (live) {
    lastLiveError_ = report_.error;
    lastLiveWarnings_ = std::move(warnings);
  }
  // Only a full evaluation writes the graph's files: say which.
  if (mode == EvalMode::Full)
    for (const auto& path : report_.filesWritten)
      log("wrote " + QString::fromStdString(path.string()));
  refresh(&report_);
  // A failure shows where it happened.
  if (!report_.ok && !report_.errorNode.empty()) editor_->focusNode(report_.errorNode);
  if (clone_->roles().found()) {
    if (!view) view = std::make_shared<const LiveView>();
    if (!radiusChosen_ && view->values.sourceMesh) {
      clone_->setBrushRadius(defaultBrushRadius(document_, clone_->roles(), view->values));
      radiusChosen_ = true;
    }
    clone_->showView(std::move(view));
  } else {
    showOutput();
  }
  // An edit's live, queued and settling evaluations together are what it cost.
  computedSinceEdit_ += report_.computed();
  if (!report_.ok)
    statusBar()->showMessage(QString::fromStdString(report_.error));
  else if (mode == EvalMode::Full)
    statusBar()->showMessage(QString("Evaluated: %1 nodes computed, %2 cached")
                                 .arg(report_.computed())
                                 .arg(report_.cacheHits()));
  else
    statusBar()->showMessage(QString("%1: %2 nodes computed since the last edit")
                                 .arg(mode == EvalMode::Live ? "Updated" : "Settled")
                                 .arg(computedSinceEdit_));
  emit evaluated(report_.ok);
  if (pendingLive_) {
    pendingLive_ = false;
    startEvaluation(EvalMode::Live);
  } else if (report_.ok && report_.historyDependent()) {
    startEvaluation(EvalMode::Settle);
  } else {
    emit becameIdle();
  }
}

void StudioWindow::stopWorker() {
  ++generation_;
  if (!worker_.joinable()) return;
  cancel_ = true;
  worker_.join();
  finished_ = true;
}

void StudioWindow::refresh(const EvalReport* report) {
  editor_->show(document_, document_.statuses(report));
}

QString StudioWindow::logText() const {
  return log_->toPlainText();
}

void StudioWindow::log(const QString& line) {
  log_->appendPlainText(line);
}

std::string StudioWindow::addNode(const std::string& typeId) {
  const QPointF at = editor_->freeSpot(document_.graph());
  const std::string error = document_.addNode(typeId, at.x(), at.y());
  edited(error);
  return error;
}

std::string StudioWindow::setParam(const std::string& node, const std::string& param,
                                   const ParamValue& value) {
  const std::string error = document_.setParam(node, param, value);
  edited(error);
  return error;
}

void StudioWindow::edited(const std::string& error) {
  if (!error.empty()) {
    log("error: " + QString::fromStdString(error));
    statusBar()->showMessage(QString::fromStdString(error));
    params_->showNode(document_, selected_);
    return;
  }
  updateUndoActions();
  updateRoles();
  computedSinceEdit_ = 0;
  evaluateLive();
  QTimer::singleShot(0, this, [this] {
    refresh(nullptr);
    params_->showNode(document_, selected_);
  });
}

void StudioWindow::undoRedo(bool undo) {
  const std::string what = undo ? document_.undoText() : document_.redoText();
  if (!(undo ? document_.undo() : document_.redo())) return;
  log(QString(undo ? "undo: " : "redo: ") + QString::fromStdString(what));
  edited({});
}

void StudioWindow::updateUndoActions() {
  setWindowModified(document_.modified());
  undoAction_->setEnabled(document_.canUndo());
  redoAction_->setEnabled(document_.canRedo());
  const std::string undo = document_.undoText(), redo = document_.redoText();
  undoAction_->setText(undo.empty() ? "&Undo" : "&Undo " + QString::fromStdString(undo));
  redoAction_->setText(redo.empty() ? "&Redo" : "&Redo " + QString::fromStdString(redo));
}

}  // namespace geobrush::studio
