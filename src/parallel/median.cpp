#include "parallel/median.h"

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "parallel/parallel_for.h"

namespace pvrt {

template <class T>
T parallelNth(std::span<const std::vector<T>> parts, size_t rank, int threads) {
  using Bits = std::conditional_t<sizeof(T) == 4, uint32_t, uint64_t>;
  constexpr int kDigit = 11;  // 2048 counters a part and pass
  constexpr int kBits = int(8 * sizeof(T));
  constexpr int kPasses = (kBits + kDigit - 1) / kDigit;
  Bits prefix = 0, prefixMask = 0;
  // The digits from the highest, the first one narrower where kBits is no multiple of kDigit.
  for (int pass = 0; pass < kPasses; ++pass) {
    const int shift = kDigit * (kPasses - 1 - pass);
    const Bits digitMask = (Bits(1) << (pass == 0 ? kBits - shift : kDigit)) - 1;
    std::vector<std::vector<size_t>> counts(parts.size());
    parallelIndices(parts.size(), threads, [&](size_t k) {
      std::vector<size_t>& count = counts[k];
      count.assign(size_t(digitMask) + 1, 0);
      for (const T v : parts[k]) {
        const Bits u = std::bit_cast<Bits>(v);
        if ((u & prefixMask) == prefix) ++count[(u >> shift) & digitMask];
      }
    });
    Bits digit = 0;
    for (;; ++digit) {
      size_t inDigit = 0;
      for (const std::vector<size_t>& count : counts) inDigit += count[size_t(digit)];
      if (rank < inDigit) break;
      rank -= inDigit;
    }
    prefix |= digit << shift;
    prefixMask |= digitMask << shift;
  }
  return std::bit_cast<T>(prefix);
}

template float parallelNth<float>(std::span<const std::vector<float>>, size_t, int);
template double parallelNth<double>(std::span<const std::vector<double>>, size_t, int);

float parallelMedian(std::span<const std::vector<float>> parts, int threads) {
  size_t n = 0;
  for (const std::vector<float>& part : parts) n += part.size();
  return n == 0 ? NAN : parallelNth(parts, n / 2, threads);
}

}  // namespace pvrt
