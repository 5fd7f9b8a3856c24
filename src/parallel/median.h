// The median of many non-negative floats held in parts, found in parallel.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace pvrt {

// The element of rank n / 2 of the values of `parts` together (n their count): what
// std::nth_element finds in their concatenation. The values must be non-negative floats
// (+0 and infinity included, no NaN, no -0), whose order as unsigned integers is their order
// as numbers: a radix select counts one digit of them a pass, every part on its own thread
// (up to `threads`, 0: threadBudget()), so 10^6 values take no one thread for long. The same
// value whatever `threads`. NaN when there are no values.
float parallelMedian(std::span<const std::vector<float>> parts, int threads);

}  // namespace pvrt
