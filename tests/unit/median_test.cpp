#include "parallel/median.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <random>

namespace pvrt {
namespace {

float nthElementMedian(const std::vector<std::vector<float>>& parts) {
  std::vector<float> all;
  for (const auto& part : parts) all.insert(all.end(), part.begin(), part.end());
  std::nth_element(all.begin(), all.begin() + all.size() / 2, all.end());
  return all[all.size() / 2];
}

// Values spread over many binades, with repeats, zeros and infinities: parts of unequal
// sizes, some empty.
std::vector<std::vector<float>> randomParts(unsigned seed, size_t count) {
  std::mt19937 rng(seed);
  std::vector<std::vector<float>> parts(rng() % 9 + 1);
  std::uniform_real_distribution<float> mantissa(0.5f, 1.0f);
  for (size_t i = 0; i < count; ++i) {
    float v = std::ldexp(mantissa(rng), int(rng() % 40) - 30);
    if (rng() % 50 == 0) v = 0;
    if (rng() % 70 == 0) v = INFINITY;
    if (rng() % 5 == 0) v = 0.25f;  // a value many share
    parts[rng() % parts.size()].push_back(v);
  }
  return parts;
}

TEST(ParallelMedian, IsWhatNthElementFindsInTheConcatenation) {
  for (unsigned seed = 1; seed <= 60; ++seed) {
    const auto parts = randomParts(seed, 1 + seed * 37 % 5000);
    const float expected = nthElementMedian(parts);
    for (int threads : {1, 2, 5}) {
      const float got = parallelMedian(parts, threads);
      EXPECT_EQ(std::bit_cast<uint32_t>(got), std::bit_cast<uint32_t>(expected))
          << "seed " << seed << ", " << threads << " threads: " << got << " against " << expected;
    }
  }
}

TEST(ParallelMedian, NeighboursDifferingInTheLastBitAreTold) {
  const float a = 1.0f, b = std::nextafter(a, 2.0f), c = std::nextafter(b, 2.0f);
  EXPECT_EQ(parallelMedian(std::vector<std::vector<float>>{{c, a}, {b}}, 2), b);
  EXPECT_EQ(parallelMedian(std::vector<std::vector<float>>{{c}, {a, b, c}}, 2), c);  // rank 2 of a b c c
  EXPECT_EQ(parallelMedian(std::vector<std::vector<float>>{{0.0f, INFINITY, INFINITY}}, 1), INFINITY);
}

// Doubles at every rank, the lowest and highest included: what nth_element puts there.
TEST(ParallelNth, FindsEveryRankOfDoubles) {
  for (unsigned seed = 1; seed <= 30; ++seed) {
    std::mt19937 rng(seed);
    std::vector<std::vector<double>> parts(rng() % 7 + 1);
    std::uniform_real_distribution<double> mantissa(0.5, 1.0);
    const size_t count = 1 + seed * 53 % 3000;
    std::vector<double> all;
    for (size_t i = 0; i < count; ++i) {
      double v = std::ldexp(mantissa(rng), int(rng() % 2000) - 1000);
      if (rng() % 40 == 0) v = 0;
      if (rng() % 60 == 0) v = INFINITY;
      if (rng() % 5 == 0) v = std::nextafter(1.0, 2.0);  // a value many share, one ulp off 1
      if (rng() % 7 == 0) v = 1.0;
      parts[rng() % parts.size()].push_back(v);
      all.push_back(v);
    }
    for (size_t rank : {size_t(0), (count - 1) / 2, count / 2, count - 1, size_t(rng() % count)}) {
      std::vector<double> sorted = all;
      std::nth_element(sorted.begin(), sorted.begin() + std::ptrdiff_t(rank), sorted.end());
      for (int threads : {1, 3}) {
        const double got = parallelNth<double>(parts, rank, threads);
        EXPECT_EQ(std::bit_cast<uint64_t>(got), std::bit_cast<uint64_t>(sorted[rank]))
            << "seed " << seed << ", rank " << rank << ", " << threads << " threads";
      }
    }
  }
}

TEST(ParallelMedian, NoValuesGiveNan) {
  EXPECT_TRUE(std::isnan(parallelMedian(std::vector<std::vector<float>>{}, 2)));
  EXPECT_TRUE(std::isnan(parallelMedian(std::vector<std::vector<float>>{{}, {}}, 2)));
}

}  // namespace
}  // namespace pvrt
