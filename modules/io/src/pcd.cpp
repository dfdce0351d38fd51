#include "trainsim/io/pcd.hpp"

#include <pcl/PCLPointCloud2.h>
#include <pcl/io/pcd_io.h>

#include "trainsim/core/error.hpp"
#include "trainsim/io/packed.hpp"

namespace trainsim::io {
namespace {

// The fields of a point as the file packs them, in order, with no padding.
struct FieldSpec {
  const char* name;
  std::uint8_t type;
  std::uint8_t size;
};
constexpr FieldSpec kFields[] = {
    {"x", pcl::PCLPointField::FLOAT32, 4},   {"y", pcl::PCLPointField::FLOAT32, 4},
    {"z", pcl::PCLPointField::FLOAT32, 4},   {"intensity", pcl::PCLPointField::FLOAT32, 4},
    {"ring", pcl::PCLPointField::UINT16, 2}, {"time", pcl::PCLPointField::FLOAT32, 4},
    {"label", pcl::PCLPointField::UINT32, 4}};
constexpr std::size_t kPointBytes = [] {
  std::size_t bytes = 0;
  for (const FieldSpec& f : kFields)
    bytes += f.size;
  return bytes;
}();

}  // namespace

std::string encodePcd(std::span<const PcdPoint> points) {
  // PCL writes the header from its field table; the points follow packed, as its binary reader
  // takes them. (PCL's binary_compressed writer puts the file out a byte at a time through an
  // ostream, 50 ms a 120 000-point scan in the run's serial commit step; this is a copy.)
  pcl::PCLPointCloud2 cloud;
  std::uint32_t offset = 0;
  for (const FieldSpec& spec : kFields) {
    pcl::PCLPointField f;
    f.name = spec.name;
    f.offset = offset;
    f.datatype = spec.type;
    f.count = 1;
    cloud.fields.push_back(f);
    offset += spec.size;
  }
  cloud.width = static_cast<pcl::uindex_t>(points.size());
  cloud.height = 1;
  cloud.is_dense = true;
  cloud.point_step = offset;
  cloud.row_step = cloud.point_step * cloud.width;
  pcl::PCDWriter writer;
  std::string out =
      writer.generateHeaderBinary(cloud, Eigen::Vector4f::Zero(), Eigen::Quaternionf::Identity());
  if (out.empty())
    throw RuntimeError("PCL could not make a PCD header");
  out += "DATA binary\n";
  const std::size_t header = out.size();
  out.resize(header + points.size() * kPointBytes);
  char* p = out.data() + header;
  for (const PcdPoint& q : points) {
    putPacked(p, q.x);
    putPacked(p, q.y);
    putPacked(p, q.z);
    putPacked(p, q.intensity);
    putPacked(p, q.ring);
    putPacked(p, q.time);
    putPacked(p, q.label);
  }
  return out;
}

}  // namespace trainsim::io
