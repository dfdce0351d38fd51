#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace trainsim::scene {

/// A semantic class id: the value in label files and semantic images (resources/classes.json).
using ClassId = std::uint16_t;
/// A material id (resources/materials.json).
using MaterialId = std::uint16_t;
/// An object's instance id, unique in the whole scene and a pure function of what the object is
/// (see instanceId()); 0 for "stuff" without instances (terrain, ballast, sleepers).
using InstanceId = std::uint64_t;

using Rgb = std::array<std::uint8_t, 3>;

/// One row of the class table.
struct SemanticClass {
  ClassId id = 0;
  std::string name;
  Rgb colour{};
  bool thing = false;     ///< has instances
  int semantickitti = 0;  ///< nearest SemanticKITTI label id (0 = unlabelled)
  int railsem19 = 255;    ///< nearest RailSem19 class index (255 = void)
  std::string osdar23;    ///< nearest OSDaR23 ontology key, empty for none
};

/// One row of the material table: what the LiDAR needs (Lambertian-Beckmann backscatter) and
/// what the cameras need (colour and a procedural texture).
struct Material {
  MaterialId id = 0;
  std::string name;
  double reflectance = 0.0;  ///< ρ at 905 nm (a Lambertian surface's head-on return)
  double k_d = 1.0, k_s = 0.0;
  double roughness = 1.0;  ///< Beckmann RMS facet slope m
  double max_incidence_rad = 0.0;
  double cos_max_incidence = 1.0;  ///< its cosine, for the LiDAR's per-return test
  Rgb colour{};
  /// A light source's colour (sRGB), drawn as it is whatever the lighting: a signal's lit lamp.
  /// Black for every surface that only reflects.
  Rgb emission{};
  double texture_contrast = 0.0;
  double texture_size_m = 1.0;
  std::string source;
  bool emits() const { return emission != Rgb{}; }
};

/// The class table, read once from the embedded resources/classes.json (ids dense from 0).
std::span<const SemanticClass> classes();
/// The material table, read once from the embedded resources/materials.json (ids dense from 0).
std::span<const Material> materials();
/// The id of the class or material with this name; throws RuntimeError for an unknown name (a
/// programming error: the names the code uses are checked by a test against the tables).
ClassId classId(std::string_view name);
MaterialId materialId(std::string_view name);
const SemanticClass& semanticClass(ClassId id);
const Material& material(MaterialId id);

/// The class ids the generators use, by name; `SemanticTable.NamedIdsMatchTheTable` checks
/// every one against resources/classes.json.
namespace cls {
inline constexpr ClassId kUnlabelled = 0, kRail = 1, kSleeper = 2, kTrackbed = 3, kTerrain = 4,
                         kVegetation = 5, kTree = 6, kTrunk = 7, kRock = 8, kBuilding = 9,
                         kPole = 10, kWire = 11, kFence = 12, kPlatform = 13, kTunnel = 14,
                         kBridge = 15, kSignal = 16, kSky = 17, kPerson = 18, kCar = 19,
                         kAnimal = 20, kFog = 21;
}  // namespace cls

/// The material ids the generators use, checked by `SemanticTable.NamedIdsMatchTheTable`.
namespace mat {
inline constexpr MaterialId kNone = 0, kRailHead = 1, kRailWeb = 2, kConcrete = 3,
                            kBallastGranite = 4, kBallastBasalt = 5, kGrass = 6, kDryGrass = 7,
                            kSoil = 8, kLeaves = 9, kNeedles = 10, kBark = 11, kRock = 12,
                            kBrick = 13, kPlaster = 14, kRoofTile = 15, kGalvanisedSteel = 16,
                            kCopper = 17, kAsphalt = 18, kPaintedMetal = 19, kRetroreflector = 20,
                            kSignalLensRed = 21, kSignalLensYellow = 22, kSignalLensGreen = 23,
                            kSignalLampRed = 24, kSignalLampYellow = 25, kSignalLampGreen = 26,
                            kClothing = 27, kSkin = 28, kCarPaint = 29, kGlass = 30, kRubber = 31,
                            kHide = 32;
}  // namespace mat

/// What made an object, the top byte of its instance id.
enum class InstanceSource : std::uint8_t {
  kNone = 0,
  kTrackAsset = 1,  ///< along a layout track: (track id, item kind, index along the track)
  kObject = 2,      ///< a trackside object: (tile, index in the tile)
};
/// A track asset's instance id: source | track (12 bits) | kind (8 bits) | index (36 bits).
InstanceId trackAssetInstance(int track_id, int kind, std::int64_t index);
/// A trackside object's instance id: source | tile i (16 bits) | tile j (16 bits) | index (24).
InstanceId objectInstance(int tile_i, int tile_j, std::uint32_t index);
InstanceSource instanceSource(InstanceId id);
/// What trackAssetInstance() put into an id.
struct TrackAsset {
  int track_id = 0;
  int kind = 0;
  std::int64_t index = 0;
};
/// The track asset an id names; nothing for an id of another source.
std::optional<TrackAsset> trackAsset(InstanceId id);

}  // namespace trainsim::scene
