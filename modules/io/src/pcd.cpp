#include "trainsim/io/pcd.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include <cstddef>
#include <cstring>
#include <sstream>

#include "trainsim/core/error.hpp"

namespace trainsim::io {
namespace {

pcl::PCLPointField field(const char* name, std::size_t offset, std::uint8_t type) {
  pcl::PCLPointField f;
  f.name = name;
  f.offset = static_cast<pcl::uindex_t>(offset);
  f.datatype = type;
  f.count = 1;
  return f;
}

}  // namespace

std::string encodePcd(std::span<const PcdPoint> points) {
  // The fields point into PcdPoint as it lies in memory, so the points are copied as they are
  // and PCL's writer picks each field out by its offset.
  pcl::PCLPointCloud2 cloud;
  using F = pcl::PCLPointField;
  cloud.fields = {field("x", offsetof(PcdPoint, x), F::FLOAT32),
                  field("y", offsetof(PcdPoint, y), F::FLOAT32),
                  field("z", offsetof(PcdPoint, z), F::FLOAT32),
                  field("intensity", offsetof(PcdPoint, intensity), F::FLOAT32),
                  field("ring", offsetof(PcdPoint, ring), F::UINT16),
                  field("time", offsetof(PcdPoint, time), F::FLOAT32),
                  field("label", offsetof(PcdPoint, label), F::UINT32)};
  cloud.width = static_cast<pcl::uindex_t>(points.size());
  cloud.height = 1;
  cloud.is_dense = true;
  cloud.point_step = sizeof(PcdPoint);
  cloud.row_step = cloud.point_step * cloud.width;
  cloud.data.resize(points.size_bytes());
  if (!points.empty())
    std::memcpy(cloud.data.data(), points.data(), points.size_bytes());
  std::ostringstream out;
  pcl::PCDWriter writer;
  if (writer.writeBinaryCompressed(out, cloud) != 0)
    throw RuntimeError("PCL could not encode a PCD point cloud");
  return std::move(out).str();
}

}  // namespace trainsim::io
