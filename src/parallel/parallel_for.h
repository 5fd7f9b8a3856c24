// The one parallel seam. Rendering code hands over a WorkPlan and a function that
// renders one item on one worker; this decides which worker runs which item.
// parallel_for_omp.cpp is the only file that knows about OpenMP.
#pragma once

#include <functional>

#include "parallel/schedule.h"

namespace pvrt {

enum class Backend { Serial, OpenMP };

// Calls renderItem(itemIndex, worker) for every item of the plan exactly once, with
// worker in [0, workers). Serial runs items in order on the calling thread as worker 0.
void parallelFor(Backend backend, int workers, const WorkPlan& plan,
                 const std::function<void(size_t item, int worker)>& renderItem);

// Worker count OpenMP would use by default (OMP_NUM_THREADS or the cores).
int defaultThreadCount();

}  // namespace pvrt
