// The MPI backend: the paper's distributed rendering. Every rank holds the whole scene
// (and its own BVH); the image is cut by the chosen strategy, rendered with OpenMP
// threads inside each rank, and gathered on rank 0.
//
// Memory model (per rank, W x H image, P ranks; a pixel travels as 12 bytes of RGB, 3 for an
// 8-bit output, and 4 more with a load map):
//   every rank has a full-size film (12 W H bytes of address space) but only touches the
//   pages of its share;
//   gather:             rank 0 also receives all shares at once (12 W H bytes, or 3 W H);
//   recursive-doubling: a rank still in round k holds up to 2^k shares; only rank 0 ever
//                       holds them all.
#pragma once

#include <cstdint>
#include <vector>

#include "render/renderer.h"

namespace pvrt {

enum class GatherMethod { Gatherv, RecursiveDoubling };

struct DistributedSettings {
  GatherMethod gather = GatherMethod::Gatherv;
  bool masterRenders = true;  // dynamic: rank 0's threads render too (its thread 0 between answers)
  // The image travels as 8-bit sRGB, encoded on every rank (3 bytes a pixel instead of 12),
  // for an output that is 8-bit anyway: the same bytes in the file.
  bool eightBit = false;
  int slowRank = -1;          // testing aid: this rank sleeps `slowMillis` per item
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
  RenderResult render;           // on rank 0: the image (unless eightBit), load and totals
  std::vector<uint8_t> rgb8;     // on rank 0 with eightBit: the image as encodeSrgb8 gives it
  int width = 0, height = 0;     // on rank 0: the image's (its region's, with a region)
  std::vector<RankStats> ranks;  // on rank 0: one entry per rank
};

const char* gatherName(GatherMethod g);
GatherMethod parseGather(const std::string& name);  // throws pvrt::Error(Usage)

// Collective over all ranks; the image is complete on rank 0 only.
DistributedResult renderDistributed(const Scene& scene, const RenderSettings& settings,
                                    const DistributedSettings& distributed);

}  // namespace pvrt
