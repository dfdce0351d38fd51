// Counter-based random streams: known answers, independence from thread count and order,
// statistics, stream independence.

#include <gtest/gtest.h>

#include <algorithm>

#include <cmath>
#include <thread>
#include <vector>

#include "trainsim/core/hash.hpp"
#include "trainsim/core/random.hpp"

namespace trainsim {
namespace {

TEST(Fnv1a64, MatchesPublishedTestVectors) {
  EXPECT_EQ(fnv1a64(""), 0xcbf29ce484222325ULL);
  EXPECT_EQ(fnv1a64("a"), 0xaf63dc4c8601ec8cULL);
  EXPECT_EQ(fnv1a64("foobar"), 0x85944171f73967e8ULL);
}

TEST(RandomStream, PhiloxMatchesRandom123KnownAnswer) {
  // Random123's kat_vectors: philox4x64-10, counter 0 and key 0.
  const auto b = RandomStream(0, std::uint64_t{0}).bits(0);
  EXPECT_EQ(b[0], 0x16554d9eca36314cULL);
  EXPECT_EQ(b[1], 0xdb20fe9d672d0fdcULL);
  EXPECT_EQ(b[2], 0xd7e772cee186176bULL);
  EXPECT_EQ(b[3], 0x7e68b68aec7ba23bULL);
}

TEST(RandomStream, IsAPureFunctionOfSeedStreamAndIndex) {
  const RandomStream a(42, "sensors.imus[0].accel");
  const RandomStream b(42, "sensors.imus[0].accel");
  for (std::uint64_t i : {0ULL, 1ULL, 1000ULL, 1ULL << 40}) {
    EXPECT_EQ(a.normal4(i), b.normal4(i));
  }
  EXPECT_NE(a.bits(0), RandomStream(43, "sensors.imus[0].accel").bits(0));
  EXPECT_NE(a.bits(0), RandomStream(42, "sensors.imus[0].gyro").bits(0));
  EXPECT_NE(a.bits(0), a.bits(1));
  EXPECT_NE(a.bits(0), a.bits(0, 1));
}

std::vector<double> drawWithThreads(int threads, std::size_t n) {
  const RandomStream stream(7, "thread-independence");
  std::vector<double> out(n);
  std::vector<std::thread> pool;
  // Interleaved partition: each thread takes every `threads`-th block, so the order in which
  // indices are drawn differs completely between thread counts.
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t] {
      for (std::size_t block = static_cast<std::size_t>(t); block < n / 4;
           block += static_cast<std::size_t>(threads)) {
        const auto v = stream.normal4(block);
        for (std::size_t j = 0; j < 4; ++j)
          out[block * 4 + j] = v[j];
      }
    });
  }
  for (auto& th : pool)
    th.join();
  return out;
}

TEST(RandomStream, ResultsDoNotDependOnThreadCountOrOrder) {
  constexpr std::size_t kN = 400'000;
  const auto reference = drawWithThreads(1, kN);
  for (int threads : {2, 3, 8}) {
    EXPECT_EQ(drawWithThreads(threads, kN), reference) << threads << " threads";
  }
}

TEST(RandomStream, NormalsHaveZeroMeanAndUnitVariance) {
  const RandomStream s(1, "stats");
  constexpr std::uint64_t kBlocks = 250'000;  // 1e6 values
  double sum = 0, sum2 = 0, sum4 = 0;
  for (std::uint64_t i = 0; i < kBlocks; ++i) {
    for (double x : s.normal4(i)) {
      sum += x;
      sum2 += x * x;
      sum4 += x * x * x * x;
    }
  }
  const double n = 4.0 * kBlocks;
  // 5-sigma bounds: sd(mean) = 1/sqrt(n), sd(var) = sqrt(2/n), sd(4th moment) = sqrt(96/n).
  EXPECT_NEAR(sum / n, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sum2 / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sum4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));
}

TEST(RandomStream, UniformsLieInOpenClosedUnitIntervalWithCorrectMoments) {
  const RandomStream s(1, "uniform");
  constexpr std::uint64_t kBlocks = 250'000;
  double sum = 0, sum2 = 0;
  for (std::uint64_t i = 0; i < kBlocks; ++i) {
    for (double u : s.uniform4(i)) {
      ASSERT_GT(u, 0.0);
      ASSERT_LE(u, 1.0);
      sum += u;
      sum2 += u * u;
    }
  }
  const double n = 4.0 * kBlocks;
  EXPECT_NEAR(sum / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n));
  EXPECT_NEAR(sum2 / n - (sum / n) * (sum / n), 1.0 / 12.0, 1e-3);
}

TEST(RandomStream, DistinctStreamsAreUncorrelated) {
  const RandomStream a(5, "stream-a");
  const RandomStream b(5, "stream-b");
  constexpr std::uint64_t kBlocks = 250'000;
  double sxy = 0;
  for (std::uint64_t i = 0; i < kBlocks; ++i) {
    const auto x = a.normal4(i);
    const auto y = b.normal4(i);
    for (int j = 0; j < 4; ++j)
      sxy += x[j] * y[j];
  }
  const double n = 4.0 * kBlocks;
  EXPECT_NEAR(sxy / n, 0.0, 5.0 / std::sqrt(n));
}

// The keyed ziggurats (64 and 32 bits a deviate): moments, tails against the normal CDF, and
// purity in (seed, stream, index).
void expectZigguratNormals(void (RandomStream::*normals)(std::uint64_t, double*, std::size_t)
                               const) {
  const RandomStream s(11, "zig");
  const int n = 2'000'000;
  double sum = 0, sum2 = 0, sum4 = 0;
  int beyond2 = 0, beyond3 = 0, beyond4 = 0;
  for (int i = 0; i < n / 4; ++i) {
    double x[4];
    (s.*normals)(static_cast<std::uint64_t>(i), x, 4);
    for (double v : x) {
      sum += v;
      sum2 += v * v;
      sum4 += v * v * v * v;
      beyond2 += std::abs(v) > 2;
      beyond3 += std::abs(v) > 3;
      beyond4 += std::abs(v) > 4;
    }
  }
  EXPECT_NEAR(sum / n, 0.0, 5.0 / std::sqrt(n));
  EXPECT_NEAR(sum2 / n, 1.0, 5.0 * std::sqrt(2.0 / n));
  EXPECT_NEAR(sum4 / n, 3.0, 5.0 * std::sqrt(96.0 / n));
  // P(|x| > t) = erfc(t/√2); counts within 5σ of the binomial.
  auto expectTail = [&](int count, double t) {
    const double p = std::erfc(t / std::sqrt(2.0));
    EXPECT_NEAR(count, n * p, 5 * std::sqrt(n * p * (1 - p)) + 1) << t;
  };
  expectTail(beyond2, 2);
  expectTail(beyond3, 3);
  expectTail(beyond4, 4);
  double a[5], b[5], c[5];
  (s.*normals)(77, a, 5);
  (RandomStream(11, "zig").*normals)(77, b, 5);
  (RandomStream(12, "zig").*normals)(77, c, 5);
  EXPECT_TRUE(std::equal(a, a + 5, b));
  EXPECT_FALSE(std::equal(a, a + 5, c));
}

TEST(RandomStream, ZigguratNormalsMatchTheNormalDistribution) {
  expectZigguratNormals(&RandomStream::normals);
}

TEST(RandomStream, CompactZigguratNormalsMatchTheNormalDistribution) {
  expectZigguratNormals(&RandomStream::compactNormals);
  // Two deviates a word: the first of n does not depend on n, and adjacent pairs are not
  // correlated (each half of a word is its own deviate).
  const RandomStream s(3, "pairs");
  double one[1], nine[9];
  s.compactNormals(5, one, 1);
  s.compactNormals(5, nine, 9);
  EXPECT_EQ(one[0], nine[0]);
  const int pairs = 500'000;
  double sxy = 0;
  for (int i = 0; i < pairs; ++i) {
    double x[2];
    s.compactNormals(static_cast<std::uint64_t>(i), x, 2);
    sxy += x[0] * x[1];
  }
  EXPECT_NEAR(sxy / pairs, 0.0, 5.0 / std::sqrt(pairs));
}

TEST(RandomCursor, SavedPositionContinuesTheSameSequence) {
  const RandomStream s(9, "cursor");
  RandomCursor straight(s);
  std::vector<double> expected;
  for (int i = 0; i < 11; ++i)
    expected.push_back(i % 3 == 0 ? straight.uniform() : straight.normal());

  RandomCursor first(s);
  std::vector<double> got;
  for (int i = 0; i < 5; ++i)
    got.push_back(i % 3 == 0 ? first.uniform() : first.normal());
  RandomCursor resumed(s);
  resumed.seek(first.position());
  for (int i = 5; i < 11; ++i)
    got.push_back(i % 3 == 0 ? resumed.uniform() : resumed.normal());
  EXPECT_EQ(got, expected);
}

}  // namespace
}  // namespace trainsim
