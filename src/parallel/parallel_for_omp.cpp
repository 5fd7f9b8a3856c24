// The only file that knows about OpenMP.
#include <omp.h>

#include "parallel/parallel_for.h"

namespace pvrt {

namespace {

void runOpenMP(int workers, const WorkPlan& plan, const std::function<void(size_t, int)>& renderItem) {
  const long n = long(plan.items.size());
  if (!plan.owner.empty()) {
    // Static ownership (block, cyclic): each thread walks the items it owns.
#pragma omp parallel num_threads(workers)
    {
      const int me = omp_get_thread_num();
      for (long i = 0; i < n; ++i)
        if (plan.owner[size_t(i)] == me) renderItem(size_t(i), me);
    }
    return;
  }
  switch (plan.strategy) {
    case Strategy::Static:
      omp_set_schedule(omp_sched_static, plan.chunk);
      break;
    case Strategy::Dynamic:
      omp_set_schedule(omp_sched_dynamic, plan.chunk);
      break;
    case Strategy::Guided:
      omp_set_schedule(omp_sched_guided, plan.chunk);
      break;
    case Strategy::Tiles:
      omp_set_schedule(omp_sched_dynamic, 1);
      break;
    default:  // Runtime: keep what OMP_SCHEDULE set
      break;
  }
#pragma omp parallel for schedule(runtime) num_threads(workers)
  for (long i = 0; i < n; ++i) renderItem(size_t(i), omp_get_thread_num());
}

}  // namespace

void parallelFor(Backend backend, int workers, const WorkPlan& plan,
                 const std::function<void(size_t item, int worker)>& renderItem) {
  if (backend == Backend::Serial || workers <= 1) {
    for (size_t i = 0; i < plan.items.size(); ++i)
      renderItem(i, 0);
    return;
  }
  runOpenMP(workers, plan, renderItem);
}

int defaultThreadCount() { return omp_get_max_threads(); }

}  // namespace pvrt
