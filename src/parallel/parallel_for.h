// The one parallel seam. Rendering code hands over a WorkPlan and a function that
// renders one item on one worker; this decides which worker runs which item.
// parallel_for_omp.cpp is the only file that knows about OpenMP.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>

#include "parallel/schedule.h"
#include "parallel/threads.h"

namespace pvrt {

enum class Backend { Serial, OpenMP };

// Calls renderItem(itemIndex, worker) for every item of the plan exactly once, with
// worker in [0, workers). Serial runs items in order on the calling thread as worker 0.
void parallelFor(Backend backend, int workers, const WorkPlan& plan,
                 const std::function<void(size_t item, int worker)>& renderItem);

// Runs team(worker) on `workers` threads at once, worker 0 on the calling thread (so it
// may make MPI calls under MPI_THREAD_FUNNELED), each pinned as parallelFor's are. For
// schedules that hand out work themselves (the MPI backend's dynamic queue).
void parallelTeam(int workers, const std::function<void(int worker)>& team);

// Calls body(i) for every i in [0, n) on up to `threads` threads (0: threadBudget()),
// one index at a time to whichever thread is free: for the stages before and after the
// render (load, build, encode), whose results must not depend on which thread did what.
// Indices are handed out in increasing order, so a body may wait for the work of a body
// with a smaller index (it has started). An exception thrown by a body ends the program,
// so bodies catch their own.
void parallelIndices(size_t n, int threads, const std::function<void(size_t)>& body);

// Ends the threads that parallel regions left waiting for the next one. OpenMP keeps them
// spinning for a while after a region (libgomp: GOMP_SPINCOUNT turns, 10-20 ms on a recent
// Xeon), on CPUs that another process of the node may need: an MPI rank calls this when its
// work is done, so that rank 0's write stage gets the node's CPUs at once. A later region
// starts new threads.
void releaseIdleThreads();

// [0, n) cut into consecutive blocks of nearly equal size, for passes over big arrays whose
// per-block results are then combined in block order: about four blocks for each of up to
// `threads` threads (0: threadBudget()), none under `grain` indices (one block for a small n).
// The combination must not depend on where the cuts fall (mins, maxes and integer sums do
// not), since the thread count moves them.
struct Blocks {
  Blocks(size_t n, int threads, size_t grain) : n(n) {
    const size_t team = size_t(threads > 0 ? threads : threadBudget());
    count = std::max<size_t>(1, std::min(4 * team, n / std::max<size_t>(grain, 1)));
  }
  size_t begin(size_t b) const { return n * b / count; }
  size_t end(size_t b) const { return n * (b + 1) / count; }
  size_t n, count;
};

// Calls body(block, begin, end) for every block, on up to `threads` threads.
inline void parallelBlocks(const Blocks& blocks, int threads,
                           const std::function<void(size_t block, size_t begin, size_t end)>& body) {
  parallelIndices(blocks.count, threads, [&](size_t b) { body(b, blocks.begin(b), blocks.end(b)); });
}

}  // namespace pvrt
