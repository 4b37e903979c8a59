#include "param_panel.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QDoubleSpinBox>
#include <QFormLayout>
#include <QLabel>
#include <QLineEdit>
#include <QSpinBox>
#include <limits>

namespace geobrush::studio {

ParamPanel::ParamPanel(const NodeRegistry& registry, QWidget* parent)
    : QWidget(parent), registry_(registry), form_(new QFormLayout(this)) {}

void ParamPanel::showNode(const StudioDocument& document, const std::string& node) {
  while (form_->rowCount() > 0)
    form_->removeRow(0);
  const auto it = document.graph().nodes.find(node);
  if (it == document.graph().nodes.end()) return;
  const NodeType* type = registry_.find(it->second.type);
  form_->addRow(new QLabel(QString::fromStdString(node + " (" + it->second.type + ")")));
  if (!type) {
    form_->addRow(new QLabel("No loaded plugin provides this type: its params are kept as saved."));
    return;
  }
  for (const ParamDecl& decl : type->params) {
    const auto value = it->second.params.find(decl.name);
    QWidget* editor =
        editorFor(decl, value != it->second.params.end() ? value->second : decl.defaultValue, node);
    editor->setToolTip(QString::fromStdString(decl.doc));
    form_->addRow(QString::fromStdString(decl.name), editor);
  }
}

QWidget* ParamPanel::editorFor(const ParamDecl& decl, const ParamValue& value,
                               const std::string& node) {
  const std::string name = decl.name;
  auto changed = [this, node, name](const ParamValue& v) {
    if (onChange) onChange(node, name, v);
  };
  const double lo = decl.min.value_or(-std::numeric_limits<double>::max());
  const double hi = decl.max.value_or(std::numeric_limits<double>::max());
  switch (decl.kind) {
    case ParamKind::Bool: {
      auto* box = new QCheckBox;
      box->setChecked(std::get<bool>(value));
      connect(box, &QCheckBox::toggled, box, [changed](bool on) { changed(on); });
      return box;
    }
    case ParamKind::Int: {
      auto* spin = new QSpinBox;
      spin->setRange(int(std::max(lo, double(std::numeric_limits<int>::min()))),
                     int(std::min(hi, double(std::numeric_limits<int>::max()))));
      spin->setValue(int(std::get<std::int64_t>(value)));
      connect(spin, &QSpinBox::editingFinished, spin,
              [spin, changed] { changed(std::int64_t(spin->value())); });
      return spin;
    }
    case ParamKind::Double: {
      auto* spin = new QDoubleSpinBox;
      spin->setDecimals(6);
      spin->setRange(lo, hi);
      spin->setValue(std::get<double>(value));
      connect(spin, &QDoubleSpinBox::editingFinished, spin,
              [spin, changed] { changed(spin->value()); });
      return spin;
    }
    case ParamKind::Enum: {
      auto* combo = new QComboBox;
      for (const auto& choice : decl.choices)
        combo->addItem(QString::fromStdString(choice));
      combo->setCurrentText(QString::fromStdString(std::get<std::string>(value)));
      connect(combo, &QComboBox::textActivated, combo,
              [changed](const QString& text) { changed(text.toStdString()); });
      return combo;
    }
    default: {
      // Strings, paths, vectors and lists in their command-line text form ("a,b,c").
      auto* line = new QLineEdit(QString::fromStdString(formatParam(value)));
      connect(line, &QLineEdit::editingFinished, line, [this, line, decl, node] {
        try {
          if (onChange) onChange(node, decl.name, parseParamText(decl, line->text().toStdString()));
        } catch (const std::exception&) {
          // Passed on as text: the document's check names what is wrong.
          if (onChange) onChange(node, decl.name, line->text().toStdString());
        }
      });
      return line;
    }
  }
}

}  // namespace geobrush::studio
