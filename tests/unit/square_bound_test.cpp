#include "core/square_bound.h"

#include <gtest/gtest.h>

#include <random>

namespace pvrt {
namespace {

// The bound itself passes and the next double up fails, for bounds of every size.
TEST(SquareBound, IsTheLastDoubleWhoseRootPasses) {
  std::mt19937_64 gen(5);
  std::uniform_real_distribution<double> mantissa(1, 2);
  std::uniform_int_distribution<int> exponent(-300, 300);
  for (int k = 0; k < 20000; ++k) {
    const double bound = std::ldexp(mantissa(gen), exponent(gen));
    const double x = squareBound(bound);
    ASSERT_LE(std::sqrt(x), bound) << bound;
    ASSERT_GT(std::sqrt(std::nextafter(x, INFINITY)), bound) << bound;
  }
  EXPECT_EQ(squareBound(0), 0);
  EXPECT_GT(squareBound(2), 4);  // the root of the next double up still rounds to 2
}

// Compared with the squared length, it decides every vector near the bound as the length.
TEST(SquareBound, DecidesAsTheLengthDoes) {
  std::mt19937_64 gen(7);
  std::uniform_real_distribution<double> u(-1, 1);
  const double bound = 0.5e-7 * 1e-6;  // the size of the tracer's bufferServes bound
  const double limit = squareBound(bound);
  int near = 0;
  for (int k = 0; k < 200000; ++k) {
    const double a = u(gen) * bound, b = u(gen) * bound, c = std::sqrt(std::fabs(bound * bound - a * a - b * b));
    const double s = 1 + u(gen) * 1e-15;  // within a few ulps of the bound
    const double x = a * s, y = b * s, z = c * s;
    const double squared = x * x + y * y + z * z;
    near += std::fabs(std::sqrt(squared) - bound) < 4e-16 * bound;
    ASSERT_EQ(std::sqrt(squared) <= bound, squared <= limit) << x << " " << y << " " << z;
  }
  EXPECT_GT(near, 1000);
}

}  // namespace
}  // namespace pvrt
