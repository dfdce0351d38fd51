#pragma once

#include <array>
#include <cstdint>
#include <string_view>

namespace trainsim {

/// Stable 64-bit identifier of a named random stream (FNV-1a of the UTF-8 bytes), so that a
/// stream's numbers depend on its name, never on the order in which streams are created.
std::uint64_t streamId(std::string_view name);

/// A counter-based random stream: the numbers drawn at counter `index` are a pure function of
/// (seed, stream, index), computed with Random123's Philox4x64-10 (key = {seed, stream},
/// counter = {index, lane-block, 0, 0}). Nothing is stored between draws, so any thread can
/// draw any index in any order and the results are identical to a sequential run.
class RandomStream {
 public:
  RandomStream(std::uint64_t seed, std::uint64_t stream) : seed_(seed), stream_(stream) {}
  RandomStream(std::uint64_t seed, std::string_view name) : RandomStream(seed, streamId(name)) {}

  std::uint64_t seed() const { return seed_; }
  std::uint64_t stream() const { return stream_; }

  /// Four independent uniformly distributed 64-bit words for (index, block).
  std::array<std::uint64_t, 4> bits(std::uint64_t index, std::uint64_t block = 0) const;
  /// Four independent uniforms in the open-closed interval (0, 1], 53-bit resolution.
  std::array<double, 4> uniform4(std::uint64_t index, std::uint64_t block = 0) const;
  /// Four independent standard normal deviates (Box-Muller on the four words).
  std::array<double, 4> normal4(std::uint64_t index, std::uint64_t block = 0) const;

  /// `n` independent standard normals for `index`, by the ziggurat method (Marsaglia & Tsang
  /// 2000, 128 layers, 32-bit resolution, separate bits for the layer index) on the 64-bit
  /// words of blocks 0, 1, … of `index` in turn (rejections draw further words). A pure
  /// function of (seed, stream, index, n). About five times cheaper per deviate than the
  /// Box–Muller of normal4(), for high-rate sensor noise. Written here because none of the
  /// project's dependencies offers a counter-keyed fast normal generator.
  void normals(std::uint64_t index, double* out, std::size_t n) const;
  /// The same from 32 bits a deviate, two to a word (the layer from 7 bits, the value from the
  /// other 25: a resolution of 2⁻²⁴ of the layer's width, 1e-9 m of a 2 cm range noise): half
  /// the generator's work, for the LiDAR's noise on every return. Another sequence than
  /// normals()'s.
  void compactNormals(std::uint64_t index, double* out, std::size_t n) const;
  double uniform(std::uint64_t index) const { return uniform4(index)[0]; }
  double normal(std::uint64_t index) const { return normal4(index)[0]; }

 private:
  std::uint64_t seed_;
  std::uint64_t stream_;
};

/// Sequential reader over a RandomStream for code that draws an unknown number of values per
/// step: it walks the counter forward and uses all four lanes of every block. Its whole state
/// is the position, so it can be saved and restored exactly (for --resume).
class RandomCursor {
 public:
  explicit RandomCursor(const RandomStream& stream, std::uint64_t start_index = 0)
      : stream_(stream), next_index_(start_index) {}

  double normal();
  double uniform();

  enum class Kind : std::uint8_t { kNone, kNormal, kUniform };
  /// Everything needed to continue exactly where the cursor is (for --resume): the block
  /// index held in the buffer, the next lane in it and what the buffer holds.
  struct Position {
    std::uint64_t index = 0;
    unsigned lane = 4;  // 4: nothing buffered, `index` is the next block to draw
    Kind kind = Kind::kNone;
  };
  Position position() const;
  void seek(const Position& p);

 private:
  void refill(Kind kind);

  RandomStream stream_;
  std::uint64_t next_index_;
  std::array<double, 4> buffer_{};
  unsigned lane_ = 4;
  Kind kind_ = Kind::kNone;
};

}  // namespace trainsim
