#include "parallel/median.h"

#include <bit>
#include <cmath>
#include <cstdint>

#include "parallel/parallel_for.h"

namespace pvrt {

float parallelMedian(std::span<const std::vector<float>> parts, int threads) {
  size_t n = 0;
  for (const std::vector<float>& part : parts) n += part.size();
  if (n == 0) return NAN;
  size_t rank = n / 2;  // among the values that share the digits found so far
  uint32_t prefix = 0, prefixMask = 0;
  // Digits of 11, 11 and 10 bits, the highest first: 2048 counters a part and pass.
  for (const int shift : {21, 10, 0}) {
    const uint32_t digitMask = (uint32_t(1) << (shift == 0 ? 10 : 11)) - 1;
    std::vector<std::vector<size_t>> counts(parts.size());
    parallelIndices(parts.size(), threads, [&](size_t k) {
      std::vector<size_t>& count = counts[k];
      count.assign(size_t(digitMask) + 1, 0);
      for (const float v : parts[k]) {
        const uint32_t u = std::bit_cast<uint32_t>(v);
        if ((u & prefixMask) == prefix) ++count[(u >> shift) & digitMask];
      }
    });
    uint32_t digit = 0;
    for (;; ++digit) {
      size_t inDigit = 0;
      for (const std::vector<size_t>& count : counts) inDigit += count[digit];
      if (rank < inDigit) break;
      rank -= inDigit;
    }
    prefix |= digit << shift;
    prefixMask |= digitMask << shift;
  }
  return std::bit_cast<float>(prefix);
}

}  // namespace pvrt
