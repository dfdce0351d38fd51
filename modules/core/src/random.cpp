#include "trainsim/core/random.hpp"

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
