// The one parallel seam. Rendering code hands over a WorkPlan and a function that
// renders one item on one worker; this decides which worker runs which item.
// parallel_for_omp.cpp is the only file that knows about OpenMP.
#pragma once

#include <functional>

#include "parallel/schedule.h"
#include "parallel/threads.h"

namespace pvrt {

enum class Backend { Serial, OpenMP };

// Calls renderItem(itemIndex, worker) for every item of the plan exactly once, with
// worker in [0, workers). Serial runs items in order on the calling thread as worker 0.
void parallelFor(Backend backend, int workers, const WorkPlan& plan,
                 const std::function<void(size_t item, int worker)>& renderItem);

// Calls body(i) for every i in [0, n) on up to `threads` threads (0: threadBudget()),
// one index at a time to whichever thread is free: for the stages before and after the
// render (load, build, encode), whose results must not depend on which thread did what.
// Indices are handed out in increasing order, so a body may wait for the work of a body
// with a smaller index (it has started). An exception thrown by a body ends the program,
// so bodies catch their own.
void parallelIndices(size_t n, int threads, const std::function<void(size_t)>& body);

}  // namespace pvrt
