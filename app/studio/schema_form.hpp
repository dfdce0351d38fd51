#pragma once

#include <QLabel>
#include <QTabWidget>
#include <QWidget>
#include <map>
#include <string>

#include "scenario_document.hpp"
#include "trainsim/scenario/param.hpp"

class QVBoxLayout;

namespace trainsim::studio {

/// The parameter panels, generated from the scenario schema: one tab per top-level section,
/// a group per object, an editable list per array, one field per parameter with its unit,
/// range and description as tooltip. A parameter added to the schema appears here without
/// studio code. Edits go to the document (undoable); the validator's messages are shown at
/// the field they name. Every field's editor has the parameter's JSON path as objectName
/// ("route.generator.length_m", "sensors.imus[0].rate_hz").
class SchemaForm : public QTabWidget {
  Q_OBJECT

 public:
  SchemaForm(const scenario::Param& root, ScenarioDocument* document, QWidget* parent = nullptr);

  /// The editor of a leaf parameter, or nullptr.
  QWidget* editor(const QString& path) const;
  /// The validator's message shown at a field or group ("" when it is valid).
  QString errorAt(const QString& path) const;
  /// Brings the tab and field of `path` into view.
  void reveal(const QString& path);

 private:
  struct Field {
    const scenario::Param* param = nullptr;
    QWidget* editor = nullptr;
    QLabel* error = nullptr;
  };
  struct Group {
    const scenario::Param* param = nullptr;
    QWidget* box = nullptr;
    QVBoxLayout* body = nullptr;  ///< arrays: holds the items
    QLabel* error = nullptr;
  };

  void rebuild();
  QWidget* buildObject(const scenario::Param& p, const std::string& path);
  QWidget* buildArray(const scenario::Param& p, const std::string& path);
  void fillArray(const std::string& path);
  QWidget* buildField(const scenario::Param& p, const std::string& path);
  void showValue(const std::string& path);
  void onChanged(const QString& path);
  void showProblems();
  void forget(const std::string& prefix);
  void commitText(const std::string& path, const QString& text);

  const scenario::Param& root_;
  ScenarioDocument* doc_;
  std::map<std::string, Field> fields_;
  std::map<std::string, Group> groups_;
  std::map<std::string, QString> errors_;
};

}  // namespace trainsim::studio
