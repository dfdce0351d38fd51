#include "trainsim/core/random.hpp"

#include <cmath>

#include "trainsim/core/hash.hpp"

#include <Random123/philox.h>
#include <Random123/boxmuller.hpp>
#include <Random123/uniform.hpp>

namespace trainsim {

std::uint64_t streamId(std::string_view name) {
  return fnv1a64(name);
}

std::array<std::uint64_t, 4> RandomStream::bits(std::uint64_t index, std::uint64_t block) const {
  using Rng = r123::Philox4x64;
  const Rng::key_type key = {{seed_, stream_}};
  const Rng::ctr_type ctr = {{index, block, 0, 0}};
  const Rng::ctr_type r = Rng()(ctr, key);
  return {r[0], r[1], r[2], r[3]};
}

std::array<double, 4> RandomStream::uniform4(std::uint64_t index, std::uint64_t block) const {
  const auto b = bits(index, block);
  return {r123::u01<double>(b[0]), r123::u01<double>(b[1]), r123::u01<double>(b[2]),
          r123::u01<double>(b[3])};
}

std::array<double, 4> RandomStream::normal4(std::uint64_t index, std::uint64_t block) const {
  const auto b = bits(index, block);
  const r123::double2 p = r123::boxmuller(b[0], b[1]);
  const r123::double2 q = r123::boxmuller(b[2], b[3]);
  return {p.x, p.y, q.x, q.y};
}

namespace {

// Ziggurat tables for the standard normal, 128 layers (Marsaglia & Tsang, JSS 5(8), 2000).
struct Ziggurat {
  std::array<std::uint32_t, 128> k{};
  std::array<double, 128> w{};
  std::array<double, 128> f{};
  Ziggurat() {
    const double m1 = 2147483648.0, vn = 9.91256303526217e-3;
    double dn = 3.442619855899, tn = dn;
    const double q = vn / std::exp(-0.5 * dn * dn);
    k[0] = static_cast<std::uint32_t>((dn / q) * m1);
    k[1] = 0;
    w[0] = q / m1;
    w[127] = dn / m1;
    f[0] = 1.0;
    f[127] = std::exp(-0.5 * dn * dn);
    for (int i = 126; i >= 1; --i) {
      dn = std::sqrt(-2.0 * std::log(vn / dn + std::exp(-0.5 * dn * dn)));
      k[static_cast<std::size_t>(i + 1)] = static_cast<std::uint32_t>((dn / tn) * m1);
      tn = dn;
      f[static_cast<std::size_t>(i)] = std::exp(-0.5 * dn * dn);
      w[static_cast<std::size_t>(i)] = dn / m1;
    }
  }
};

// Built at start-up rather than on first use, so the draws pay no guard check.
const Ziggurat kZiggurat;

// 64-bit words of (index, block 0, 1, ...) in order.
class Words {
 public:
  Words(const RandomStream& s, std::uint64_t index) : s_(s), index_(index) {}
  std::uint64_t next() {
    if (lane_ == 4) {
      buf_ = s_.bits(index_, block_++);
      lane_ = 0;
    }
    return buf_[lane_++];
  }
  double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * 0x1.0p-53; }

 private:
  const RandomStream& s_;
  std::uint64_t index_;
  std::uint64_t block_ = 0;
  std::array<std::uint64_t, 4> buf_{};
  unsigned lane_ = 4;
};

// One ziggurat deviate from draws of (hz, iz): hz a signed value scaled to 2^31, iz the layer
// (independent bits); rejections take further draws and words.
template <typename Draw>
double zigguratNormal(Words& words, Draw draw) {
  const Ziggurat& z = kZiggurat;
  for (;;) {
    const auto [hz, iz] = draw();
    const std::uint32_t mag = hz < 0 ? static_cast<std::uint32_t>(-(static_cast<std::int64_t>(hz)))
                                     : static_cast<std::uint32_t>(hz);
    const double x = hz * z.w[iz];
    if (mag < z.k[iz])
      return x;
    if (iz == 0) {  // the tail beyond r
      constexpr double r = 3.442619855899;
      double xt, yt;
      do {
        xt = -std::log(words.uniform()) / r;
        yt = -std::log(words.uniform());
      } while (yt + yt < xt * xt);
      return hz > 0 ? r + xt : -r - xt;
    }
    if (z.f[iz] + words.uniform() * (z.f[iz - 1] - z.f[iz]) < std::exp(-0.5 * x * x))
      return x;
  }
}

struct Draw {
  std::int32_t hz;
  std::size_t iz;
};

// A 32-bit draw: the layer from the low 7 bits, the value from the 25 above them.
Draw halfDraw(std::uint32_t h) {
  return {static_cast<std::int32_t>(h & ~127u), h & 127u};
}

}  // namespace

void RandomStream::normals(std::uint64_t index, double* out, std::size_t n) const {
  Words words(*this, index);
  const auto draw = [&words] {
    const std::uint64_t word = words.next();
    return Draw{static_cast<std::int32_t>(static_cast<std::uint32_t>(word >> 32)), word & 127u};
  };
  for (std::size_t i = 0; i < n; ++i)
    out[i] = zigguratNormal(words, draw);
}

void RandomStream::compactNormals(std::uint64_t index, double* out, std::size_t n) const {
  Words words(*this, index);
  std::uint64_t word = 0;
  bool high = false;  // the current word's high half is still to be used
  const auto draw = [&] {
    if (high) {
      high = false;
      return halfDraw(static_cast<std::uint32_t>(word >> 32));
    }
    word = words.next();
    high = true;
    return halfDraw(static_cast<std::uint32_t>(word));
  };
  for (std::size_t i = 0; i < n; ++i)
    out[i] = zigguratNormal(words, draw);
}

void RandomCursor::refill(Kind kind) {
  buffer_ = kind == Kind::kNormal ? stream_.normal4(next_index_) : stream_.uniform4(next_index_);
  ++next_index_;
  lane_ = 0;
  kind_ = kind;
}

double RandomCursor::normal() {
  if (lane_ >= 4 || kind_ != Kind::kNormal) {
    refill(Kind::kNormal);
  }
  return buffer_[lane_++];
}

double RandomCursor::uniform() {
  if (lane_ >= 4 || kind_ != Kind::kUniform) {
    refill(Kind::kUniform);
  }
  return buffer_[lane_++];
}

RandomCursor::Position RandomCursor::position() const {
  if (lane_ >= 4) {
    return {next_index_, 4, Kind::kNone};
  }
  return {next_index_ - 1, lane_, kind_};
}

void RandomCursor::seek(const Position& p) {
  next_index_ = p.index;
  lane_ = 4;
  kind_ = Kind::kNone;
  if (p.lane < 4 && p.kind != Kind::kNone) {
    refill(p.kind);
    lane_ = p.lane;
  }
}

}  // namespace trainsim
