#pragma once
// Private to the LiDAR module: a ring's returns put in the order KITTI's files have.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "trainsim/lidar/lidar.hpp"

namespace trainsim::lidar::detail {

// Orders one ring's slots (`columns` × `returns` keys, kNoReturn where there is no return, and
// their points `from`) by key, ties by slot: the points into `to`, and `order` as key bits << 32
// | slot; returns how many there are. A counting sort into one bucket per column's width of
// azimuth, moving each point as it is placed, then an insertion sort that only has to order
// the few entries sharing a bucket: linear time, and the points are read and written once,
// each in one sweep.
std::size_t orderRing(const float* keys, const LidarPoint* from, std::size_t columns,
                      std::size_t returns, std::vector<std::uint64_t>& order,
                      std::vector<std::uint32_t>& start, LidarPoint* to);

}  // namespace trainsim::lidar::detail
