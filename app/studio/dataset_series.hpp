#pragma once

#include <QString>
#include <QStringList>
#include <QVector>
#include <map>
#include <string>
#include <vector>

#include "trainsim/scenario/param.hpp"

namespace trainsim::studio {

/// A CSV file of a dataset read by column: header names to values (empty cells are NaN).
struct CsvTable {
  std::map<std::string, QVector<double>> columns;
  int rows = 0;
  bool has(const std::string& name) const { return columns.count(name) != 0; }
  const QVector<double>& at(const std::string& name) const;
};

/// Reads a dataset CSV (comma-separated, one header line, numbers). Throws IoError naming the
/// file when it cannot be read or a cell is not a number.
CsvTable readCsv(const QString& path);

/// One sensor of a generated dataset, as its manifest lists it.
struct DatasetSensor {
  std::string name;
  std::string kind;   ///< the sensor's kind in the manifest ("imu", "gnss", …)
  QStringList files;  ///< absolute paths, the readings file first
  /// A copy of its item in the dataset's scenario.json (sensors.<kind list>[i]); null if the
  /// scenario has no sensor of that name.
  scenario::Json config;
};

/// A generated dataset as the studio reads it: scenario.json, the manifest and its sensors.
struct DatasetFiles {
  QString root;
  scenario::Json scenario;  ///< OUT/scenario.json
  std::vector<DatasetSensor> sensors;
};

/// Reads OUT/scenario.json and OUT/manifest.json (through io::DatasetLayout and io::Manifest);
/// throws IoError/ConfigError naming the file.
DatasetFiles findDatasetFiles(const QString& root);

}  // namespace trainsim::studio
