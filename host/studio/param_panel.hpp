// The parameter panel: the selected node's params, one editor each, built from the node type's
// declarations (kind, range, choices; the doc as tooltip). An edit is handed to onChange, which
// checks it against the declaration; the panel shows the graph's values again afterwards.
#pragma once

#include <QWidget>
#include <functional>
#include <string>

#include "studio_document.hpp"

class QFormLayout;

namespace geobrush::studio {

class ParamPanel : public QWidget {
 public:
  explicit ParamPanel(const NodeRegistry& registry, QWidget* parent = nullptr);

  // The params of `node` in the document (none for an empty name or a missing type).
  void showNode(const StudioDocument& document, const std::string& node);

  std::function<void(const std::string& node, const std::string& param, const ParamValue& value)>
      onChange;

 private:
  QWidget* editorFor(const ParamDecl& decl, const ParamValue& value, const std::string& node);

  const NodeRegistry& registry_;
  QFormLayout* form_;
};

}  // namespace geobrush::studio
