#include "trainsim/scene/semantics.hpp"

#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "trainsim/core/error.hpp"

namespace trainsim::embedded {
extern const std::string_view classes_json;
extern const std::string_view materials_json;
}  // namespace trainsim::embedded

namespace trainsim::scene {
namespace {

Rgb readRgb(const nlohmann::json& j) {
  return {j.at(0).get<std::uint8_t>(), j.at(1).get<std::uint8_t>(), j.at(2).get<std::uint8_t>()};
}

// The tables are the project's own resources, embedded at build time: a malformed one is a
// build defect, reported as a RuntimeError naming the file.
template <typename Row, typename Read>
std::vector<Row> readTable(std::string_view text, const char* file, const char* key, Read read) {
  std::vector<Row> rows;
  try {
    const auto doc = nlohmann::json::parse(text);
    for (const auto& item : doc.at(key)) {
      Row row = read(item);
      if (row.id != rows.size())
        throw RuntimeError(fmt::format("resources/{}: ids must run 0, 1, 2, ... (found {} at {})",
                                       file, row.id, rows.size()));
      rows.push_back(std::move(row));
    }
  } catch (const nlohmann::json::exception& e) {
    throw RuntimeError(fmt::format("resources/{}: {}", file, e.what()));
  }
  return rows;
}

const std::vector<SemanticClass>& classTable() {
  static const auto table = readTable<SemanticClass>(
      embedded::classes_json, "classes.json", "classes", [](const auto& j) {
        SemanticClass c;
        c.id = j.at("id").template get<ClassId>();
        c.name = j.at("name").template get<std::string>();
        c.colour = readRgb(j.at("colour"));
        c.thing = j.at("thing").template get<bool>();
        c.semantickitti = j.at("semantickitti").template get<int>();
        c.railsem19 = j.at("railsem19").template get<int>();
        if (!j.at("osdar23").is_null())
          c.osdar23 = j.at("osdar23").template get<std::string>();
        return c;
      });
  return table;
}

const std::vector<Material>& materialTable() {
  static const auto table = readTable<Material>(
      embedded::materials_json, "materials.json", "materials", [](const auto& j) {
        Material m;
        m.id = j.at("id").template get<MaterialId>();
        m.name = j.at("name").template get<std::string>();
        m.reflectance = j.at("reflectance").template get<double>();
        m.k_d = j.at("k_d").template get<double>();
        m.k_s = j.at("k_s").template get<double>();
        m.roughness = j.at("roughness").template get<double>();
        m.max_incidence_rad =
            j.at("max_incidence_deg").template get<double>() * std::numbers::pi / 180.0;
        m.cos_max_incidence = std::cos(m.max_incidence_rad);
        m.colour = readRgb(j.at("colour"));
        if (j.contains("emission"))
          m.emission = readRgb(j.at("emission"));
        m.texture_contrast = j.at("texture_contrast").template get<double>();
        m.texture_size_m = j.at("texture_size_m").template get<double>();
        m.source = j.at("source").template get<std::string>();
        return m;
      });
  return table;
}

template <typename Row>
std::uint16_t idByName(const std::vector<Row>& rows, std::string_view name, const char* what) {
  for (const auto& row : rows)
    if (row.name == name)
      return static_cast<std::uint16_t>(row.id);
  throw RuntimeError(fmt::format("unknown {} '{}'", what, name));
}

}  // namespace

std::span<const SemanticClass> classes() {
  return classTable();
}
std::span<const Material> materials() {
  return materialTable();
}
ClassId classId(std::string_view name) {
  return idByName(classTable(), name, "class");
}
MaterialId materialId(std::string_view name) {
  return idByName(materialTable(), name, "material");
}

const SemanticClass& semanticClass(ClassId id) {
  if (id >= classTable().size())
    throw RuntimeError(fmt::format("unknown class id {}", id));
  return classTable()[id];
}
const Material& material(MaterialId id) {
  if (id >= materialTable().size())
    throw RuntimeError(fmt::format("unknown material id {}", id));
  return materialTable()[id];
}

InstanceId trackAssetInstance(int track_id, int kind, std::int64_t index) {
  return (InstanceId{static_cast<std::uint8_t>(InstanceSource::kTrackAsset)} << 56) |
         ((static_cast<InstanceId>(track_id) & 0xFFFu) << 44) |
         ((static_cast<InstanceId>(kind) & 0xFFu) << 36) |
         (static_cast<InstanceId>(index) & 0xFFFFFFFFFull);
}
std::optional<TrackAsset> trackAsset(InstanceId id) {
  if (instanceSource(id) != InstanceSource::kTrackAsset)
    return std::nullopt;
  return TrackAsset{static_cast<int>((id >> 44) & 0xFFFu), static_cast<int>((id >> 36) & 0xFFu),
                    static_cast<std::int64_t>(id & 0xFFFFFFFFFull)};
}
InstanceId objectInstance(int tile_i, int tile_j, std::uint32_t index) {
  return (InstanceId{static_cast<std::uint8_t>(InstanceSource::kObject)} << 56) |
         ((static_cast<InstanceId>(static_cast<std::uint16_t>(tile_i))) << 40) |
         ((static_cast<InstanceId>(static_cast<std::uint16_t>(tile_j))) << 24) |
         (static_cast<InstanceId>(index) & 0xFFFFFFu);
}
InstanceSource instanceSource(InstanceId id) {
  return static_cast<InstanceSource>(id >> 56);
}

}  // namespace trainsim::scene
