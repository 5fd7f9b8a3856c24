// The median (or any rank) of many non-negative floats or doubles held in parts, found in
// parallel.
#pragma once

#include <cstddef>
#include <span>
#include <vector>

namespace pvrt {

// The element of rank `rank` of the values of `parts` together (rank < their count n): what
// std::nth_element puts there in their concatenation. The values must be non-negative (+0 and
// infinity included, no NaN, no -0), whose order as unsigned integers is their order as
// numbers: a radix select counts one digit of them a pass, every part on its own thread (up
// to `threads`, 0: threadBudget()), so 10^6 values take no one thread for long. The same value
// whatever `threads`. T is float or double.
template <class T>
T parallelNth(std::span<const std::vector<T>> parts, size_t rank, int threads);

// parallelNth of rank n / 2 (the upper median); NaN when there are no values.
float parallelMedian(std::span<const std::vector<float>> parts, int threads);

}  // namespace pvrt
