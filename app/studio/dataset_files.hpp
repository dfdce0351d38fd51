#pragma once
// What the studio's scan view reads of a dataset besides its scans: the sensors a sequence has,
// the projection between a LiDAR and a camera from calib.txt, instances.csv and the PNG images.
#include <QDir>
#include <QString>
#include <QStringList>
#include <map>
#include <optional>

#include "trainsim/camera/kitti_projection.hpp"
#include "trainsim/io/kitti_calib.hpp"
#include "trainsim/io/png.hpp"

namespace trainsim::studio {

// The LiDARs and cameras a sequence has, by their folders (io::DatasetLayout's names): LiDAR i
// writes velodyne[_i]/, camera i whichever of image_N/, depth_N/, semantic_N/ and instance_N/
// it was asked for; listed by their first folder's name, in their sensors' order.
QStringList lidarFolders(const QDir& sequence);
QStringList cameraFolders(const QDir& sequence);

// The LiDAR's projection into the camera, from calib.txt's lines for the pair: Tr or Tr_N,
// P_{camera + 2} and D_{camera + 2} when the camera has a lens; none, with `problem` saying why,
// when they are missing or malformed.
std::optional<camera::KittiProjection> pairProjection(const io::KittiCalib& calib, int lidar,
                                                      int camera, QString& problem);

// One row of instances.csv: what an instance id stands for.
struct InstanceRow {
  QString cls, track, state;
};

// instances.csv by instance id (older datasets have fewer columns: those missing stay empty);
// empty when there is none.
std::map<int, InstanceRow> readInstances(const QString& path);

// A PNG of the dataset, or none when that output is off or the file is unreadable.
std::optional<io::PngImage> readPng(const QString& path);

}  // namespace trainsim::studio
