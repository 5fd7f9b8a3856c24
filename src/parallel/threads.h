// How many threads a process's stages use, and which CPUs they may take. Every stage
// (load, build, render, encode) asks threadBudget() instead of counting cores itself, so
// that MPI ranks sharing a node divide its CPUs instead of each starting a thread per core.
#pragma once

#include <vector>

namespace pvrt {

// The CPUs this process may run on (its affinity mask), in increasing order; never empty.
std::vector<int> allowedCpus();

// This process's share of its CPUs when several processes (the MPI ranks of one node whose
// masks are the same) run on them: it is `slot` of `slots`.
struct CpuShare {
  int slot = 0;
  int slots = 1;
};
void setCpuShare(CpuShare share);
CpuShare cpuShare();

// The most threads pvrt takes (--threads, OMP_NUM_THREADS): libgomp aborts when it cannot
// start as many as it is asked for (OMP_NUM_THREADS=100000).
inline constexpr int kMaxThreads = 1024;
// OMP_NUM_THREADS as pvrt reads it: 0 when unset or empty, -1 when it is not a whole number
// from 1 to kMaxThreads (optionally followed by OpenMP's ",inner,..." list), else the number.
// main() refuses -1 with a usage error before any command runs.
int threadsFromEnvironment();

// The threads each stage uses by default: what setThreadBudget() set (--threads), else
// OMP_NUM_THREADS when it is set, else this process's share of its allowed CPUs (at least 1).
int threadBudget();
void setThreadBudget(int threads);  // 0: back to the default

// Restricts the whole process to its share of CPUs (a run of threadBudget() of them) when
// it shares its mask with other processes and they all fit, so that load, build and
// render threads of different ranks never meet on a CPU; the share is then the process's
// own mask (slot 0 of 1). Nothing happens when thread binding was asked of OpenMP
// (OMP_PROC_BIND, OMP_PLACES, GOMP_CPU_AFFINITY) or PVRT_PIN_THREADS=0. True when pinned.
bool pinProcessToShare();

// Whether pvrt may choose CPUs for its threads (see pinProcessToShare).
bool pinningAllowed();

// Once the other processes of the share (the node's other MPI ranks) have no more work,
// this one takes what they all had: the mask it started with, if pinProcessToShare had
// narrowed it, and as many threads as the sharers had together (at most one a CPU).
// For MPI rank 0's write stage, which would otherwise encode the whole image on the
// threads of one rank (one, in a run of one thread a rank). Returns the new budget.
int takeWholeShare();

}  // namespace pvrt
