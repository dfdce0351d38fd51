#include "classes_yaml.hpp"

#include <fmt/format.h>

#include <numeric>

#include "trainsim/scene/semantics.hpp"

namespace trainsim::sim {

std::string classesYaml(std::span<const std::int64_t> class_points, int sequence,
                        std::string_view counted) {
  const auto classes = scene::classes();
  const std::int64_t total =
      std::accumulate(class_points.begin(), class_points.end(), std::int64_t{0});
  std::string out =
      "# TrainSim semantic classes (resources/classes.json; docs/SEMANTICS.md) in the layout of\n"
      "# SemanticKITTI's config (semantic-kitti-api config/semantic-kitti.yaml), so its tools\n"
      "# read labels/*.label unchanged: label = class | instance << 16.\n"
      "name: \"trainsim\"\n";
  const auto section = [&](const char* key, std::string_view comment, auto value) {
    out += fmt::format("{}:{}\n", key, comment);
    for (const scene::SemanticClass& c : classes)
      out += fmt::format("  {}: {}\n", c.id, value(c));
  };
  section("labels", "",
          [](const scene::SemanticClass& c) { return fmt::format("\"{}\"", c.name); });
  section("color_map", " # bgr", [](const scene::SemanticClass& c) {
    return fmt::format("[{}, {}, {}]", c.colour[2], c.colour[1], c.colour[0]);
  });
  section("content", fmt::format(" # share of {} in this sequence", counted),
          [&](const scene::SemanticClass& c) {
            const std::int64_t n = c.id < class_points.size() ? class_points[c.id] : 0;
            return fmt::format("{:.9f}", total > 0 ? static_cast<double>(n) / total : 0.0);
          });
  // Learning ids are the class ids; 0 (unlabelled) is ignored.
  section("learning_map", "",
          [](const scene::SemanticClass& c) { return fmt::format("{}", c.id); });
  section("learning_map_inv", "",
          [](const scene::SemanticClass& c) { return fmt::format("{}", c.id); });
  section("learning_ignore", "",
          [](const scene::SemanticClass& c) { return c.id == 0 ? "True" : "False"; });
  out += fmt::format("split:\n  train:\n    - {}\n  valid: []\n  test: []\n", sequence);
  section("things", " # classes with instances (upper 16 bits of a label)",
          [](const scene::SemanticClass& c) { return c.thing ? "True" : "False"; });
  section("semantickitti_map", " # the nearest SemanticKITTI label id",
          [](const scene::SemanticClass& c) { return fmt::format("{}", c.semantickitti); });
  section("railsem19_map", " # the nearest RailSem19 class index (255: void)",
          [](const scene::SemanticClass& c) { return fmt::format("{}", c.railsem19); });
  section("osdar23_map", " # the nearest OSDaR23 ontology class",
          [](const scene::SemanticClass& c) {
            return c.osdar23.empty() ? std::string("null") : fmt::format("\"{}\"", c.osdar23);
          });
  return out;
}

}  // namespace trainsim::sim
