#include "dataset_series.hpp"

#include <QFile>
#include <QFileInfo>
#include <cmath>
#include <filesystem>
#include <limits>

#include "trainsim/core/error.hpp"
#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/scenario/scenario.hpp"
#include "trainsim/sim/sensor_registry.hpp"

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
  const std::filesystem::path dir = root.toStdString();
  const std::string scenario_file = (dir / io::DatasetLayout::kScenario).string();
  out.scenario = scenario::parseJson(scenario::readScenarioText(scenario_file), scenario_file);
  // The manifest lists every sensor with its files, wherever dataset.sequence put them.
  for (const io::ManifestSensor& s : io::Manifest::read(dir).sensors) {
    const scenario::Json* config = sim::findSensorConfig(out.scenario, s.name);
    DatasetSensor sensor{s.name, s.kind, {}, config ? *config : scenario::Json()};
    for (const std::string& f : s.files)
      sensor.files << QString::fromStdString((dir / f).string());
    if (!sensor.files.isEmpty() && QFileInfo::exists(sensor.files.front()))
      out.sensors.push_back(std::move(sensor));
  }
  return out;
}

}  // namespace trainsim::studio
