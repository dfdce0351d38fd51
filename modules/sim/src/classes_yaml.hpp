#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace trainsim::sim {

/// classes.yaml: the class table (resources/classes.json) in the layout of SemanticKITTI's
/// config (semantic-kitti-api config/semantic-kitti.yaml: labels, color_map in BGR, content,
/// learning_map, learning_map_inv, learning_ignore, split), so its tools read TrainSim's labels
/// unchanged, plus the maps to the nearest SemanticKITTI, RailSem19 and OSDaR23 classes.
/// `class_points` (by class id; may be empty) gives `content`, each class's share of what
/// `counted` names (the first LiDAR's points, or a camera's semantic pixels); `sequence` is the
/// split's only sequence.
std::string classesYaml(std::span<const std::int64_t> class_points, int sequence,
                        std::string_view counted = "the first LiDAR's points");

}  // namespace trainsim::sim
