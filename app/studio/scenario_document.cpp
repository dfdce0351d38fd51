#include "scenario_document.hpp"

#include <QDir>
#include <QFileInfo>
#include <QUndoCommand>

#include "trainsim/io/file_io.hpp"
#include "trainsim/sim/schema.hpp"

namespace trainsim::studio {
namespace {

class SetValueCommand : public QUndoCommand {
 public:
  SetValueCommand(ScenarioDocument* doc, std::string path, scenario::Json before,
                  scenario::Json after, const QString& text)
      : QUndoCommand(text),
        doc_(doc),
        path_(std::move(path)),
        before_(std::move(before)),
        after_(std::move(after)) {}

  void undo() override { doc_->apply(path_, before_); }
  void redo() override { doc_->apply(path_, after_); }
  int id() const override { return 1; }
  bool mergeWith(const QUndoCommand* other) override {
    const auto* o = dynamic_cast<const SetValueCommand*>(other);
    if (o == nullptr || o->path_ != path_)
      return false;
    after_ = o->after_;
    return true;
  }

 private:
  ScenarioDocument* doc_;
  std::string path_;
  scenario::Json before_, after_;
};

// `input` laid over `filled` (the validator's resolution of it): every value the user wrote is
// kept as written, valid or not, unknown keys included; what they left out takes the filled-in
// default. Arrays merge item by item.
scenario::Json overlay(const scenario::Json& filled, const scenario::Json& input) {
  if (filled.is_object() && input.is_object()) {
    scenario::Json out = filled;
    for (auto it = input.begin(); it != input.end(); ++it)
      out[it.key()] = out.contains(it.key()) ? overlay(out[it.key()], it.value()) : it.value();
    return out;
  }
  if (filled.is_array() && input.is_array() && filled.size() == input.size()) {
    scenario::Json out = scenario::Json::array();
    for (std::size_t i = 0; i < input.size(); ++i)
      out.push_back(overlay(filled[i], input[i]));
    return out;
  }
  return input;
}

}  // namespace

ScenarioDocument::ScenarioDocument(QObject* parent) : QObject(parent) {
  newDefault();
}

void ScenarioDocument::newDefault() {
  // Every parameter present, so each one has a field to edit.
  reset(sim::loadScenario("").json(), {});
}

void ScenarioDocument::reset(scenario::Json document, QString path) {
  doc_ = std::move(document);
  path_ = std::move(path);
  undo_.clear();
  undo_.setClean();
  validate();
  emit filePathChanged(path_);
  emit changed({});
}

void ScenarioDocument::open(const QString& path) {
  const std::string file = path.toStdString();
  scenario::Json input = scenario::parseJson(scenario::readScenarioText(file), file);
  if (!input.is_object())
    throw ConfigError(file + ": a scenario is a JSON object");
  // Missing parameters get their defaults, so the form has a field for each; values the
  // validator rejects are kept as written, for the user to fix at their field.
  const scenario::Schema::Resolution r = sim::scenarioSchema().resolve(input);
  reset(overlay(r.resolved, input), QFileInfo(path).absoluteFilePath());
}

void ScenarioDocument::save(const QString& path) {
  io::writeFileAtomic(path.toStdString(), doc_.dump(2) + "\n");
  path_ = QFileInfo(path).absoluteFilePath();
  undo_.setClean();
  validate();  // relative waypoint files now resolve against the new folder
  emit filePathChanged(path_);
}

QString ScenarioDocument::baseDir() const {
  return path_.isEmpty() ? QDir::currentPath() : QFileInfo(path_).absolutePath();
}

scenario::Json ScenarioDocument::value(const std::string& path) const {
  const auto ptr = scenario::pointerFromPath(path);
  return doc_.contains(ptr) ? doc_.at(ptr) : scenario::Json();
}

void ScenarioDocument::setValue(const std::string& path, scenario::Json v, const QString& what) {
  scenario::Json before = value(path);
  if (before == v)
    return;
  const QString text = what.isEmpty() ? QString::fromStdString("Set " + path) : what;
  undo_.push(new SetValueCommand(this, path, std::move(before), std::move(v), text));
}

void ScenarioDocument::apply(const std::string& path, const scenario::Json& v) {
  const auto ptr = scenario::pointerFromPath(path);
  if (v.is_null() && doc_[ptr.parent_pointer()].is_object())
    doc_[ptr.parent_pointer()].erase(ptr.back());  // undoing the edit that added a key
  else
    doc_[ptr] = v;
  validate();
  emit changed(QString::fromStdString(path));
}

void ScenarioDocument::validate() {
  // One resolution per edit gives both the problems and the scenario to plan. As the CLI
  // does, a relative waypoint file is relative to the scenario file.
  problems_.clear();
  resolved_.reset();
  try {
    resolved_ = sim::resolveScenario(doc_, baseDir().toStdString(),
                                     path_.isEmpty() ? "<studio>" : path_.toStdString());
  } catch (const scenario::InvalidScenario& e) {
    problems_ = e.problems();
  }
  emit problemsChanged();
}

}  // namespace trainsim::studio
