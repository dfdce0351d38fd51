#pragma once

#include <QObject>
#include <QString>
#include <QUndoStack>
#include <optional>
#include <string>
#include <vector>

#include "trainsim/scenario/scenario.hpp"

namespace trainsim::studio {

/// The scenario being edited: the JSON document, the file it came from, the validator's
/// problems with it and an undo stack of edits. Every edit goes through setValue() (or a macro
/// of them) so it can be undone; the document is re-validated against the schema after each.
class ScenarioDocument : public QObject {
  Q_OBJECT

 public:
  explicit ScenarioDocument(QObject* parent = nullptr);

  /// The built-in default scenario with every parameter present.
  void newDefault();
  /// Replaces the document (open): clears undo history. `path` is "" for an unsaved document.
  void reset(scenario::Json document, QString path);
  /// Reads and parses a scenario file; throws ConfigError naming the file (unreadable or not
  /// JSON). A parsable file with problems is loaded; problems() lists them.
  void open(const QString& path);
  /// Writes the document (pretty JSON) atomically; throws IoError naming the file.
  void save(const QString& path);

  const scenario::Json& json() const { return doc_; }
  /// The value at a dotted path ("route.generator.length_m", "sensors.imus[0].rate_hz"), or
  /// null when absent.
  scenario::Json value(const std::string& path) const;
  /// Sets one value as an undoable edit named `what`. Consecutive edits of the same path merge.
  void setValue(const std::string& path, scenario::Json value, const QString& what = {});
  /// Several edits that undo as one.
  void beginMacro(const QString& what) { undo_.beginMacro(what); }
  void endMacro() { undo_.endMacro(); }

  QUndoStack* undoStack() { return &undo_; }
  const QString& filePath() const { return path_; }
  /// Folder relative waypoint files are read from (the scenario file's, else the current one).
  QString baseDir() const;
  bool isModified() const { return !undo_.isClean(); }

  const std::vector<scenario::Problem>& problems() const { return problems_; }
  /// The resolved scenario (relative files made absolute) when there are no problems.
  const std::optional<scenario::Scenario>& resolved() const { return resolved_; }

  /// Applies a value without recording it (the undo commands call this).
  void apply(const std::string& path, const scenario::Json& value);

 signals:
  /// A value changed (`path`), or the whole document did (`path` empty).
  void changed(const QString& path);
  void problemsChanged();
  void filePathChanged(const QString& path);

 private:
  void validate();

  scenario::Json doc_;
  QString path_;
  QUndoStack undo_;
  std::vector<scenario::Problem> problems_;
  std::optional<scenario::Scenario> resolved_;
};

}  // namespace trainsim::studio
