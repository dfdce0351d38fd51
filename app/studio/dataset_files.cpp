#include "dataset_files.hpp"

#include <QFile>
#include <string>

#include "trainsim/io/dataset_layout.hpp"
#include "trainsim/io/file_io.hpp"

namespace trainsim::studio {

QStringList lidarFolders(const QDir& sequence) {
  QStringList out;
  for (int i = 0; sequence.exists(QString::fromStdString(io::DatasetLayout::velodyneFolder(i)));
       ++i)
    out << QString::fromStdString(io::DatasetLayout::velodyneFolder(i));
  return out;
}

QStringList cameraFolders(const QDir& sequence) {
  const auto has = [&](int i) {
    for (const std::string& folder :
         {io::DatasetLayout::imageFolder(i), io::DatasetLayout::depthFolder(i),
          io::DatasetLayout::semanticFolder(i), io::DatasetLayout::instanceFolder(i)})
      if (sequence.exists(QString::fromStdString(folder)))
        return true;
    return false;
  };
  QStringList out;
  for (int i = 0; has(i); ++i)
    out << QString::fromStdString(io::DatasetLayout::imageFolder(i));
  return out;
}

std::optional<camera::KittiProjection> pairProjection(const io::KittiCalib& calib, int lidar,
                                                      int camera, QString& problem) {
  const std::string p_name = "P" + std::to_string(camera + 2);
  const std::string tr_name = lidar == 0 ? "Tr" : "Tr_" + std::to_string(lidar);
  const std::string d_name = "D" + std::to_string(camera + 2);
  const auto matrix = [&](const std::string& name) -> std::optional<Eigen::Matrix<double, 3, 4>> {
    const auto it = calib.find(name);
    if (it == calib.end() || it->second.size() != 12) {
      problem = QString(
                    "calib.txt has no %1 of 12 numbers: the points are not drawn on the "
                    "picture")
                    .arg(QString::fromStdString(name));
      return std::nullopt;
    }
    return Eigen::Map<const Eigen::Matrix<double, 3, 4, Eigen::RowMajor>>(it->second.data());
  };
  const auto P = matrix(p_name), Tr = matrix(tr_name);
  if (!P || !Tr)
    return std::nullopt;
  std::optional<camera::Distortion> lens;
  if (const auto d = calib.find(d_name); d != calib.end()) {
    if (d->second.size() != 5) {
      problem = QString(
                    "calib.txt's %1 is not k1 k2 p1 p2 k3: the points are not drawn on the "
                    "picture")
                    .arg(QString::fromStdString(d_name));
      return std::nullopt;
    }
    lens = camera::Distortion{d->second[0], d->second[1], d->second[2], d->second[3], d->second[4]};
  }
  std::string why;
  auto out = camera::KittiProjection::fromCalib(*P, *Tr, lens, why);
  if (!out)
    problem = QString("calib.txt's %1: %2; the points are not drawn on the picture")
                  .arg(QString::fromStdString(p_name), QString::fromStdString(why));
  return out;
}

std::map<int, InstanceRow> readInstances(const QString& path) {
  std::map<int, InstanceRow> out;
  QFile file(path);
  if (!file.open(QIODevice::ReadOnly | QIODevice::Text))
    return out;
  const QStringList header = QString::fromUtf8(file.readLine()).trimmed().split(',');
  const auto column = [&](const char* name) { return header.indexOf(name); };
  const int id = column("instance"), cls = column("class"), track = column("track"),
            state = column("state");
  while (!file.atEnd()) {
    const QStringList cells = QString::fromUtf8(file.readLine()).trimmed().split(',');
    const auto cell = [&](int i) { return i >= 0 && i < cells.size() ? cells[i] : QString(); };
    bool ok = false;
    const int key = cell(id).toInt(&ok);
    if (ok)
      out[key] = {cell(cls), cell(track), cell(state)};
  }
  return out;
}

std::optional<io::PngImage> readPng(const QString& path) {
  try {
    return io::decodePng(io::readFile(path.toStdString()));
  } catch (const std::exception&) {
    return std::nullopt;  // that output is off, or the file is unreadable: not described
  }
}

}  // namespace trainsim::studio
