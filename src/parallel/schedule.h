// How the image is cut into work items and who renders which: the paper's strategies
// as plain values. Nothing here knows about OpenMP or MPI.
//   block   contiguous row blocks, one per worker (the paper's "no load balancing")
//   cyclic  row r goes to worker r mod P (the paper's static load balancing)
//   static, dynamic, guided   rows handed out by OpenMP's schedule of that name,
//           in chunks of `chunk` rows (0: OpenMP's default)
//   runtime OpenMP's schedule(runtime), i.e. whatever OMP_SCHEDULE says
//   tiles   square tiles of `tileSize` pixels, handed out on demand
// With a granule g > 1 (pixels that must be rendered together in g x g squares: POV-Ray's
// blocks for its adaptive antialiasing) a "row" above is a band of g rows, block
// boundaries fall on multiples of g, and tile sides are rounded up to a multiple of g.
#pragma once

#include <string>
#include <vector>

namespace pvrt {

enum class Strategy { Block, Cyclic, Static, Dynamic, Guided, Runtime, Tiles };

struct ScheduleSettings {
  Strategy strategy = Strategy::Tiles;
  int chunk = 0;
  int tileSize = 32;
  int granule = 1;  // work items are cut on multiples of this (PixelSampler::blockGranule)
};

// A rectangle of pixels [x0,x1) x [y0,y1).
struct WorkItem {
  int x0, y0, x1, y1;
  long pixels() const { return long(x1 - x0) * (y1 - y0); }
};

struct WorkPlan {
  std::vector<WorkItem> items;
  // For block and cyclic: owner[i] is the worker that renders items[i]. Empty when the
  // assignment is left to the runtime (OpenMP schedules, tiles).
  std::vector<int> owner;
  Strategy strategy = Strategy::Tiles;
  int chunk = 0;
};

WorkPlan makeWorkPlan(const ScheduleSettings& s, int width, int height, int workers);

Strategy parseStrategy(const std::string& name);  // throws pvrt::Error(Usage)
const char* strategyName(Strategy s);
// Reads OMP_SCHEDULE ("dynamic,4", "guided", ...) into settings; false if unset/invalid.
bool scheduleFromEnvironment(ScheduleSettings& s);

}  // namespace pvrt
