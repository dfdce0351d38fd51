#include "dataset_series.hpp"

#include <QFile>
#include <QFileInfo>
#include <cmath>
#include <limits>

#include "trainsim/core/error.hpp"
#include "trainsim/scenario/scenario.hpp"

namespace trainsim::studio {

const QVector<double>& CsvTable::at(const std::string& name) const {
  const auto it = columns.find(name);
  if (it == columns.end())
    throw IoError("dataset file has no column " + name);
  return it->second;
}

CsvTable readCsv(const QString& path) {
  QFile f(path);
  if (!f.open(QIODevice::ReadOnly | QIODevice::Text))
    throw IoError(path.toStdString() + ": cannot read: " + f.errorString().toStdString());
  const QByteArray header = f.readLine().trimmed();
  std::vector<std::string> names;
  for (const QByteArray& n : header.split(','))
    names.push_back(n.toStdString());
  CsvTable t;
  std::vector<QVector<double>*> cols;
  for (const std::string& n : names)
    cols.push_back(&t.columns[n]);
  int line = 1;
  while (!f.atEnd()) {
    const QByteArray row = f.readLine().trimmed();
    ++line;
    if (row.isEmpty())
      continue;
    const QList<QByteArray> cells = row.split(',');
    if (cells.size() != static_cast<int>(names.size()))
      throw IoError(QString("%1:%2: %3 cells, the header has %4")
                        .arg(path)
                        .arg(line)
                        .arg(cells.size())
                        .arg(names.size())
                        .toStdString());
    for (int i = 0; i < cells.size(); ++i) {
      bool ok = true;
      const double v =
          cells[i].isEmpty() ? std::numeric_limits<double>::quiet_NaN() : cells[i].toDouble(&ok);
      if (!ok)
        throw IoError(QString("%1:%2: column %3 is not a number")
                          .arg(path)
                          .arg(line)
                          .arg(QString::fromStdString(names[static_cast<std::size_t>(i)]))
                          .toStdString());
      cols[static_cast<std::size_t>(i)]->push_back(v);
    }
    ++t.rows;
  }
  return t;
}

DatasetFiles findDatasetFiles(const QString& root) {
  DatasetFiles out;
  out.root = root;
  const std::string scenario_file = (root + "/scenario.json").toStdString();
  out.scenario = scenario::parseJson(scenario::readScenarioText(scenario_file), scenario_file);
  // The manifest lists every sensor with its files (the readings file first), wherever
  // dataset.sequence put them.
  const std::string manifest_file = (root + "/manifest.json").toStdString();
  const scenario::Json manifest =
      scenario::parseJson(scenario::readScenarioText(manifest_file), manifest_file);
  const std::map<std::string, std::map<std::string, QString>*> by_kind = {
      {"imu", &out.imus},
      {"gnss", &out.gnss},
      {"odometer", &out.odometers},
      {"balise_reader", &out.balises}};
  for (const scenario::Json& s : manifest.at("sensors")) {
    const auto it = by_kind.find(s.at("kind").get<std::string>());
    if (it == by_kind.end() || !s.contains("files") || s["files"].empty())
      continue;
    const QString file = root + "/" + QString::fromStdString(s.at("files")[0].get<std::string>());
    if (QFileInfo::exists(file))
      (*it->second)[s.at("name").get<std::string>()] = file;
  }
  return out;
}

}  // namespace trainsim::studio
