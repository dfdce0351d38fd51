#pragma once

#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace trainsim::io {

/// A KITTI calib.txt, by its lines' names: each line is "NAME: v1 v2 …" (P0–P3 and Tr, Tr_1, …
/// with 12 numbers, a 3 × 4 matrix row by row; D2, D3, … with OpenCV's five distortion
/// coefficients k1 k2 p1 p2 k3). Blank lines are skipped.
using KittiCalib = std::map<std::string, std::vector<double>, std::less<>>;

/// Parses calib.txt's `text`. Throws IoError naming `path` and the line when a line is not a
/// name, a colon and finite numbers, or a name comes twice.
KittiCalib parseKittiCalib(std::string_view text, const std::string& path);

}  // namespace trainsim::io
