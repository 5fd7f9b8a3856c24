// The MPI backend: the paper's distributed rendering. Every rank holds the whole scene
// (and its own BVH); the image is cut by the chosen strategy, rendered with OpenMP
// threads inside each rank, and gathered on rank 0.
//
// Memory model (per rank, W x H image, P ranks, 16 bytes per pixel: RGB + load):
//   every rank keeps a full-size film (16 W H bytes) but only fills its share;
//   gather:             rank 0 also receives all shares at once (16 W H bytes);
//   recursive-doubling: after round k a rank holds 2^k shares, so the last rounds hold
//                       up to the whole image on every rank of the power-of-two group.
#pragma once

#include <vector>

#include "render/renderer.h"

namespace pvrt {

enum class GatherMethod { Gatherv, RecursiveDoubling };

struct DistributedSettings {
  GatherMethod gather = GatherMethod::Gatherv;
  bool masterRenders = true;  // dynamic: rank 0's threads render too (its thread 0 between answers)
  int slowRank = -1;           // testing aid: this rank sleeps `slowMillis` per item
  int slowMillis = 0;
};

// Per-rank figures, as in the paper's figures 7 and 8.
struct RankStats {
  double computeSeconds = 0;  // rendering
  double commSeconds = 0;     // inside gathers and work requests
  double idleSeconds = 0;     // waiting for the other ranks to finish
  double wallSeconds = 0;
  long items = 0;
  long pixels = 0;
  RenderStats counts;
  double bytesSent = 0;
  std::vector<WorkerStats> threads;  // the rank's OpenMP threads
};

struct DistributedResult {
  RenderResult render;          // on rank 0: the whole image, load and totals
  std::vector<RankStats> ranks;  // on rank 0: one entry per rank
};

const char* gatherName(GatherMethod g);
GatherMethod parseGather(const std::string& name);  // throws pvrt::Error(Usage)

// Collective over all ranks; the image is complete on rank 0 only.
DistributedResult renderDistributed(const Scene& scene, const RenderSettings& settings,
                                    const DistributedSettings& distributed);

}  // namespace pvrt
