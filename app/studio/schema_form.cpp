#include "schema_form.hpp"

#include <QCheckBox>
#include <QComboBox>
#include <QFileDialog>
#include <QFormLayout>
#include <QGroupBox>
#include <QHBoxLayout>
#include <QLineEdit>
#include <QPushButton>
#include <QScrollArea>
#include <QSignalBlocker>
#include <QToolButton>
#include <QVBoxLayout>
#include <charconv>
#include <cmath>

#include "trainsim/sim/schema.hpp"

namespace trainsim::studio {
namespace {

using scenario::Json;
using scenario::Param;
using scenario::ParamType;

std::string join(const std::string& parent, const std::string& key) {
  return parent.empty() ? key : parent + "." + key;
}

QString numberText(double x) {
  return QString::number(x, 'g', 12);
}

// Description, unit, range and default: everything the schema says about a parameter.
QString tooltipOf(const Param& p) {
  QString tip = QString::fromStdString(p.description);
  if (!p.unit.empty())
    tip += "\nUnit: " + QString::fromStdString(p.unit);
  if (p.minimum || p.maximum)
    tip += "\nRange: " + (p.minimum ? numberText(*p.minimum) : QString("−∞")) + " … " +
           (p.maximum ? numberText(*p.maximum) : QString("∞"));
  if (!p.choices.empty()) {
    QStringList c;
    for (const std::string& s : p.choices)
      c << QString::fromStdString(s);
    tip += "\nOne of: " + c.join(", ");
  }
  if (!p.default_value.is_null() && p.type != ParamType::kObject && p.type != ParamType::kArray)
    tip += "\nDefault: " + QString::fromStdString(p.default_value.dump());
  if (!p.multiple_of.empty())
    tip += "\nA whole multiple of " + QString::fromStdString(p.multiple_of);
  return tip;
}

QString displayText(const Json& v) {
  if (v.is_string())
    return QString::fromStdString(v.get<std::string>());
  if (v.is_null())
    return {};
  return QString::fromStdString(v.dump());
}

// The JSON value a typed text stands for: a number when it parses as one of the parameter's
// type, otherwise the text itself, for the validator to reject at the field.
Json parseNumber(const Param& p, const QString& text) {
  const std::string s = text.trimmed().toStdString();
  if (p.type == ParamType::kInteger) {
    std::int64_t i = 0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), i);
    if (ec == std::errc() && end == s.data() + s.size() && !s.empty())
      return i;
  }
  bool ok = false;
  const double d = text.trimmed().toDouble(&ok);
  if (ok && std::isfinite(d))
    return d;
  return s;
}

QLabel* makeErrorLabel(QWidget* parent) {
  auto* l = new QLabel(parent);
  l->setStyleSheet("color: #c0392b;");
  l->setWordWrap(true);
  l->hide();
  return l;
}

}  // namespace

SchemaForm::SchemaForm(const Param& root, ScenarioDocument* document, QWidget* parent)
    : QTabWidget(parent), root_(root), doc_(document) {
  setDocumentMode(true);
  setUsesScrollButtons(true);
  rebuild();
  connect(doc_, &ScenarioDocument::changed, this, &SchemaForm::onChanged);
  connect(doc_, &ScenarioDocument::problemsChanged, this, &SchemaForm::showProblems);
}

QWidget* SchemaForm::editor(const QString& path) const {
  const auto it = fields_.find(path.toStdString());
  return it == fields_.end() ? nullptr : it->second.editor;
}

QString SchemaForm::errorAt(const QString& path) const {
  const auto it = errors_.find(path.toStdString());
  return it == errors_.end() ? QString() : it->second;
}

void SchemaForm::reveal(const QString& path) {
  std::string p = path.toStdString();
  const std::string section = p.substr(0, p.find_first_of(".["));
  int tab = -1;
  for (int i = 0; i < count(); ++i) {
    if (tabText(i).toStdString() == section || (tab < 0 && tabText(i) == "general"))
      tab = i;  // a top-level parameter lives on "general"
  }
  if (tab >= 0)
    setCurrentIndex(tab);
  if (QWidget* e = editor(path)) {
    for (QWidget* w = e; w; w = w->parentWidget()) {
      if (auto* area = qobject_cast<QScrollArea*>(w)) {
        area->ensureWidgetVisible(e);
        break;
      }
    }
    e->setFocus();
  }
}

void SchemaForm::rebuild() {
  const int current = currentIndex();
  while (count() > 0) {
    QWidget* w = widget(0);
    removeTab(0);
    w->deleteLater();
  }
  fields_.clear();
  groups_.clear();
  auto addPage = [&](const QString& title, QWidget* content, const QString& tip) {
    auto* area = new QScrollArea;
    area->setWidgetResizable(true);
    area->setWidget(content);
    const int index = addTab(area, title);
    setTabToolTip(index, tip);
  };
  // Top-level leaves (seed, ...) share a "general" page; each section gets its own.
  auto* general = new QWidget;
  auto* general_form = new QFormLayout(general);
  bool has_general = false;
  for (const Param& f : root_.fields) {
    if (f.type == ParamType::kObject || f.type == ParamType::kArray)
      continue;
    general_form->addRow(QString::fromStdString(f.key), buildField(f, f.key));
    has_general = true;
  }
  if (has_general)
    addPage("general", general, "Top-level parameters");
  else
    delete general;
  for (const Param& f : root_.fields) {
    if (f.type == ParamType::kObject)
      addPage(QString::fromStdString(f.key), buildObject(f, f.key),
              QString::fromStdString(f.description));
    else if (f.type == ParamType::kArray)
      addPage(QString::fromStdString(f.key), buildArray(f, f.key),
              QString::fromStdString(f.description));
  }
  setCurrentIndex(std::clamp(current, 0, count() - 1));
  showProblems();
}

QWidget* SchemaForm::buildObject(const Param& p, const std::string& path) {
  auto* box = new QWidget;
  auto* form = new QFormLayout(box);
  form->setFieldGrowthPolicy(QFormLayout::AllNonFixedFieldsGrow);
  auto* error = makeErrorLabel(box);
  form->addRow(error);
  groups_[path] = {&p, box, nullptr, error};
  for (const Param& f : p.fields) {
    const std::string child = join(path, f.key);
    if (f.type == ParamType::kObject || f.type == ParamType::kArray) {
      auto* group = new QGroupBox(QString::fromStdString(f.key));
      group->setToolTip(QString::fromStdString(f.description));
      auto* inner = new QVBoxLayout(group);
      inner->setContentsMargins(6, 4, 2, 4);
      inner->addWidget(f.type == ParamType::kObject ? buildObject(f, child) : buildArray(f, child));
      form->addRow(group);
    } else {
      auto* label = new QLabel(QString::fromStdString(f.key));
      label->setToolTip(tooltipOf(f));
      form->addRow(label, buildField(f, child));
    }
  }
  return box;
}

QWidget* SchemaForm::buildArray(const Param& p, const std::string& path) {
  auto* box = new QWidget;
  auto* outer = new QVBoxLayout(box);
  outer->setContentsMargins(0, 0, 0, 0);
  auto* error = makeErrorLabel(box);
  outer->addWidget(error);
  auto* body = new QVBoxLayout;
  outer->addLayout(body);
  auto* add = new QPushButton(QString("Add %1 item").arg(QString::fromStdString(p.key)));
  add->setObjectName(QString::fromStdString(path + "/add"));
  add->setToolTip(QString::fromStdString(p.description));
  outer->addWidget(add);
  connect(add, &QPushButton::clicked, this, [this, path] {
    Json doc = doc_->json();
    const auto ptr = scenario::pointerFromPath(path);
    if (!doc[ptr].is_array())
      doc[ptr] = Json::array();
    Json list = doc[ptr];
    if (!list.empty()) {
      list.push_back(list.back());  // a copy of the last item is the usual next entry
    } else {
      // An empty item resolved by the schema: every field at its default.
      doc[ptr].push_back(Json::object());
      const Json resolved = sim::scenarioSchema().resolve(doc).resolved;
      list.push_back(resolved.contains(ptr) && !resolved.at(ptr).empty() ? resolved.at(ptr).back()
                                                                         : Json::object());
    }
    doc_->setValue(path, list, QString::fromStdString("Add item to " + path));
  });
  groups_[path] = {&p, box, body, error};
  fillArray(path);
  return box;
}

void SchemaForm::fillArray(const std::string& path) {
  Group& g = groups_.at(path);
  while (QLayoutItem* item = g.body->takeAt(0)) {
    if (item->widget())
      item->widget()->deleteLater();
    delete item;
  }
  forget(path + "[");
  const Param& p = *g.param;
  const Json list = doc_->value(path);
  if (!list.is_array())
    return;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const std::string item_path = path + "[" + std::to_string(i) + "]";
    auto* item = new QGroupBox(QString::fromStdString(p.key + "[" + std::to_string(i) + "]"));
    auto* lay = new QVBoxLayout(item);
    lay->setContentsMargins(6, 4, 2, 4);
    auto* tools = new QHBoxLayout;
    auto* remove = new QToolButton;
    remove->setText("Remove");
    remove->setObjectName(QString::fromStdString(item_path + "/remove"));
    auto* up = new QToolButton;
    up->setText("Move up");
    up->setEnabled(i > 0);
    tools->addStretch();
    tools->addWidget(up);
    tools->addWidget(remove);
    lay->addLayout(tools);
    connect(remove, &QToolButton::clicked, this, [this, path, i] {
      Json l = doc_->value(path);
      l.erase(l.begin() + static_cast<std::ptrdiff_t>(i));
      doc_->setValue(path, l,
                     QString::fromStdString("Remove " + path + "[" + std::to_string(i) + "]"));
    });
    connect(up, &QToolButton::clicked, this, [this, path, i] {
      Json l = doc_->value(path);
      std::swap(l[i], l[i - 1]);
      doc_->setValue(path, l,
                     QString::fromStdString("Move " + path + "[" + std::to_string(i) + "] up"));
    });
    if (p.item->type == ParamType::kObject)
      lay->addWidget(buildObject(*p.item, item_path));
    else
      lay->addWidget(buildField(*p.item, item_path));
    g.body->addWidget(item);
  }
}

QWidget* SchemaForm::buildField(const Param& p, const std::string& path) {
  auto* cell = new QWidget;
  auto* v = new QVBoxLayout(cell);
  v->setContentsMargins(0, 0, 0, 0);
  v->setSpacing(1);
  auto* row = new QHBoxLayout;
  v->addLayout(row);
  QWidget* editor = nullptr;
  const QString name = QString::fromStdString(path);
  switch (p.type) {
    case ParamType::kBool: {
      auto* c = new QCheckBox;
      connect(c, &QCheckBox::toggled, this, [this, path](bool on) { doc_->setValue(path, on); });
      editor = c;
      break;
    }
    case ParamType::kEnum: {
      auto* c = new QComboBox;
      for (const std::string& s : p.choices)
        c->addItem(QString::fromStdString(s));
      connect(c, &QComboBox::textActivated, this,
              [this, path](const QString& text) { doc_->setValue(path, text.toStdString()); });
      editor = c;
      break;
    }
    default: {
      auto* e = new QLineEdit;
      if (p.type == ParamType::kInteger || p.type == ParamType::kNumber)
        e->setAlignment(Qt::AlignRight);
      connect(e, &QLineEdit::editingFinished, this,
              [this, path, e] { commitText(path, e->text()); });
      editor = e;
      row->addWidget(editor, 1);
      // Files get a browse button (parameters named *_file).
      if (p.type == ParamType::kString && path.size() > 5 &&
          path.compare(path.size() - 5, 5, "_file") == 0) {
        auto* browse = new QToolButton;
        browse->setText("…");
        browse->setToolTip("Choose a file");
        connect(browse, &QToolButton::clicked, this, [this, path] {
          const QString f = QFileDialog::getOpenFileName(this, "Choose a file", doc_->baseDir());
          if (!f.isEmpty())
            doc_->setValue(path, f.toStdString());
        });
        row->addWidget(browse);
      }
      break;
    }
  }
  editor->setObjectName(name);
  editor->setToolTip(tooltipOf(p));
  if (row->count() == 0)
    row->addWidget(editor, 1);
  if (!p.unit.empty()) {
    auto* unit = new QLabel(QString::fromStdString(p.unit));
    unit->setMinimumWidth(48);
    row->addWidget(unit);
  }
  auto* error = makeErrorLabel(cell);
  error->setObjectName(name + "/error");
  v->addWidget(error);
  fields_[path] = {&p, editor, error};
  showValue(path);
  return cell;
}

void SchemaForm::commitText(const std::string& path, const QString& text) {
  const Field& f = fields_.at(path);
  const Json value = (f.param->type == ParamType::kInteger || f.param->type == ParamType::kNumber)
                         ? parseNumber(*f.param, text)
                         : Json(text.toStdString());
  doc_->setValue(path, value);
}

void SchemaForm::showValue(const std::string& path) {
  const Field& f = fields_.at(path);
  const Json v = doc_->value(path);
  const QSignalBlocker block(f.editor);
  if (auto* c = qobject_cast<QCheckBox*>(f.editor))
    c->setChecked(v.is_boolean() && v.get<bool>());
  else if (auto* combo = qobject_cast<QComboBox*>(f.editor))
    combo->setCurrentText(displayText(v));
  else if (auto* e = qobject_cast<QLineEdit*>(f.editor)) {
    // Numbers show as parsed (a typed "1e3" becomes 1000 once accepted).
    const QString text = displayText(v);
    if (e->text() != text)
      e->setText(text);
  }
}

void SchemaForm::forget(const std::string& prefix) {
  for (auto it = fields_.begin(); it != fields_.end();)
    it = it->first.compare(0, prefix.size(), prefix) == 0 ? fields_.erase(it) : std::next(it);
  for (auto it = groups_.begin(); it != groups_.end();)
    it = it->first.compare(0, prefix.size(), prefix) == 0 ? groups_.erase(it) : std::next(it);
}

void SchemaForm::onChanged(const QString& qpath) {
  const std::string path = qpath.toStdString();
  if (path.empty()) {
    rebuild();
    return;
  }
  if (fields_.count(path)) {
    showValue(path);
    return;
  }
  // An array (or an object holding one) changed shape: refill the innermost list it is in.
  std::string best;
  for (const auto& [gpath, g] : groups_) {
    if (g.body && (path == gpath || path.rfind(gpath + "[", 0) == 0 ||
                   gpath.rfind(path + ".", 0) == 0 || gpath.rfind(path + "[", 0) == 0)) {
      if (path == gpath || gpath.size() > best.size())
        best = gpath;
    }
  }
  if (best.empty()) {
    rebuild();
    return;
  }
  fillArray(best);
  showProblems();
}

void SchemaForm::showProblems() {
  errors_.clear();
  for (auto& [path, f] : fields_) {
    f.error->hide();
    f.editor->setStyleSheet({});
  }
  for (auto& [path, g] : groups_)
    g.error->hide();
  for (const scenario::Problem& pr : doc_->problems()) {
    // At the field it names; else at the innermost group containing it.
    std::string at = pr.path;
    QLabel* label = nullptr;
    while (true) {
      if (auto it = fields_.find(at); it != fields_.end()) {
        label = it->second.error;
        it->second.editor->setStyleSheet("border: 1px solid #c0392b;");
        break;
      }
      if (auto it = groups_.find(at); it != groups_.end()) {
        label = it->second.error;
        break;
      }
      const std::size_t cut = at.find_last_of(".[");
      if (cut == std::string::npos)
        break;
      at = at.substr(0, cut);
    }
    const QString msg = QString::fromStdString(pr.message);
    QString& recorded = errors_[label ? at : pr.path];
    recorded = recorded.isEmpty() ? msg : recorded + "\n" + msg;
    if (label) {
      const QString prefix = at == pr.path ? QString() : QString::fromStdString(pr.path) + ": ";
      label->setText(label->isVisible() ? label->text() + "\n" + prefix + msg : prefix + msg);
      label->show();
    }
  }
}

}  // namespace trainsim::studio
