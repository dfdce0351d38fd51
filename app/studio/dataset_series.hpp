#pragma once

#include <QString>
#include <QVector>
#include <map>
#include <string>

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

/// The sensor files of a generated dataset (OUT/sequences/00), by sensor kind and name.
struct DatasetFiles {
  QString root;
  scenario::Json scenario;                                        ///< OUT/scenario.json
  std::map<std::string, QString> imus, gnss, odometers, balises;  ///< name → csv path
};

/// Reads OUT/scenario.json and finds the sensor files it declares.
DatasetFiles findDatasetFiles(const QString& root);

}  // namespace trainsim::studio
