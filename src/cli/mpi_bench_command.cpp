// `pvrt mpi-bench`: what moving an image between ranks costs, under mpirun. Ranks 0 and 1
// ping-pong messages of growing size (latency and bandwidth); then every rank sends its
// share of an image to rank 0, by MPI_Gatherv and by recursive doubling, for the ways a
// pixel can travel: 8-bit sRGB (3 bytes), half floats (6), floats (12), and pvrt's payload
// (RGB and the work count, 16). And what turning a float share into sRGB or halves costs.
// The paper's figure 11 and the cost model of docs/parallel.md come from these figures.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <numeric>
#include <string>
#include <vector>

#include <fmt/core.h>
#include <fmt/os.h>
#define IMATH_HALF_NO_LOOKUP_TABLE  // float to half only: header-only, no Imath library to link
#include <Imath/half.h>

#include "cli/commands.h"
#include "core/error.h"
#include "image/image_io.h"
#include "parallel/cluster.h"

namespace pvrt::cli {

namespace {

struct Options {
  std::string csv;
  int reps = 30;
  bool big = true;  // also an 8K image (7680 x 4320)
};

struct Figures {
  double median = 0, min = 0, max = 0;
};
Figures figures(std::vector<double> t) {
  if (t.empty()) return {};
  std::sort(t.begin(), t.end());
  return {t[t.size() / 2], t.front(), t.back()};
}

// Rank 0's seconds from a barrier to holding every share, `reps` times.
std::vector<double> timeGather(size_t bytesTotal, bool recursiveDoubling, int reps) {
  const int n = cluster::size(), me = cluster::rank();
  // Shares in whole floats: the last rank takes the remainder.
  const size_t floats = (bytesTotal + 3) / 4, share = floats / size_t(n);
  const std::vector<float> mine(me == n - 1 ? floats - share * size_t(n - 1) : share, 0.5f);
  std::vector<double> times;
  for (int k = 0; k < reps; ++k) {
    cluster::barrier();
    const auto t0 = std::chrono::steady_clock::now();
    const std::vector<float> all =
        recursiveDoubling ? cluster::gatherRecursiveDoubling(mine) : cluster::gatherv(mine);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (me == 0) {
      if (all.size() != floats) throw Error(ExitCode::Internal, "mpi-bench: the gather lost data");
      times.push_back(s);
    }
  }
  return times;
}

// Seconds to encode `pixels` float RGB pixels as 8-bit sRGB and as halves, on one thread.
std::pair<double, double> timeConversions(size_t pixels) {
  Image share(int(pixels), 1);
  for (size_t i = 0; i < share.data().size(); ++i) share.data()[i] = float(i % 1000) / 999.0f;
  auto t0 = std::chrono::steady_clock::now();
  const std::vector<uint8_t> srgb = encodeSrgb8(share);
  const double srgbS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  t0 = std::chrono::steady_clock::now();
  std::vector<Imath::half> half(share.data().size());
  std::transform(share.data().begin(), share.data().end(), half.begin(), [](float v) { return Imath::half(v); });
  const double halfS = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (srgb.empty() || half.empty()) throw Error(ExitCode::Internal, "mpi-bench: empty conversion");
  return {srgbS, halfS};
}

int runMpiBench(const Options& o) {
  cluster::Session session;
  const int me = cluster::rank(), n = cluster::size();
  std::FILE* csv = nullptr;
  if (me == 0 && !o.csv.empty()) {
    csv = std::fopen(o.csv.c_str(), "w");
    if (!csv) throw Error(ExitCode::OutputError, "cannot write \"" + o.csv + "\"");
    fmt::print(csv, "test,ranks,image,bytes_per_pixel,bytes,reps,median_us,min_us,max_us,bandwidth_gb_s\n");
  }
  const auto row = [&](const char* test, const std::string& image, int bpp, size_t bytes, const Figures& f,
                       double bandwidthBytes) {
    if (me != 0) return;
    const double gbs = f.median > 0 ? bandwidthBytes / f.median / 1e9 : 0;
    fmt::print("  {:<20}{:>6}{:>12}{:>5}{:>14}{:>12.1f}{:>12.1f}{:>12.1f}{:>10.2f}\n", test, n, image, bpp, bytes,
               f.median * 1e6, f.min * 1e6, f.max * 1e6, gbs);
    if (csv)
      fmt::print(csv, "{},{},{},{},{},{},{:.3f},{:.3f},{:.3f},{:.4f}\n", test, n, image, bpp, bytes, o.reps,
                 f.median * 1e6, f.min * 1e6, f.max * 1e6, gbs);
  };
  if (me == 0)
    fmt::print("  {:<20}{:>6}{:>12}{:>5}{:>14}{:>12}{:>12}{:>12}{:>10}\n", "test", "ranks", "image", "B/px", "bytes",
               "median us", "min us", "max us", "GB/s");
  if (n > 1) {
    for (size_t bytes : {size_t(0), size_t(8), size_t(1) << 10, size_t(64) << 10, size_t(1) << 20,
                         size_t(3072000), size_t(16384000)}) {
      const int reps = bytes >= (size_t(1) << 20) ? std::max(5, o.reps / 3) : o.reps * 10;
      std::vector<double> rtt = cluster::pingPong(bytes, reps);
      for (double& t : rtt) t /= 2;  // one way
      row("pingpong-one-way", "-", 0, bytes, figures(rtt), double(bytes));
    }
  }
  struct Size {
    const char* name;
    size_t pixels;
    int reps;
  };
  std::vector<Size> sizes = {{"1280x800", size_t(1280) * 800, o.reps}};
  if (o.big) sizes.push_back({"7680x4320", size_t(7680) * 4320, std::max(2, o.reps / 10)});
  for (const Size& size : sizes)
    for (int bpp : {3, 6, 12, 16})
      for (bool rd : {false, true}) {
        if (n == 1 && rd) continue;
        const size_t bytes = size.pixels * size_t(bpp);
        row(rd ? "gather-recursive-dbl" : "gather-gatherv", size.name, bpp, bytes,
            figures(timeGather(bytes, rd, size.reps)), double(bytes));
      }
  // Conversions of one rank's share of a 1280x800 image, on rank 0.
  if (me == 0) {
    const size_t share = size_t(1280) * 800 / size_t(n);
    std::vector<double> srgb, half;
    for (int k = 0; k < std::max(3, o.reps / 3); ++k) {
      const auto [s, h] = timeConversions(share);
      srgb.push_back(s);
      half.push_back(h);
    }
    row("convert-srgb8", "1280x800/P", 12, share * 12, figures(srgb), double(share * 12));
    row("convert-half", "1280x800/P", 12, share * 12, figures(half), double(share * 12));
  }
  if (csv) std::fclose(csv);
  return 0;
}

}  // namespace

Command addMpiBenchCommand(CLI::App& app) {
  auto o = std::make_shared<Options>();
  CLI::App* c = app.add_subcommand(
      "mpi-bench", "Under mpirun: ping-pong latency and bandwidth, and gathering an image on rank 0 "
                   "(MPI_Gatherv and recursive doubling) as 8-bit sRGB, half, float and pvrt's 16-byte payload");
  c->add_option("--csv", o->csv, "Also write the figures to this CSV file (rank 0)");
  c->add_option("--reps", o->reps, "Repetitions of each gather (ping-pong: ten times as many)")
      ->check(CLI::Range(1, 100000))
      ->capture_default_str();
  c->add_flag("!--no-8k", o->big, "Leave out the 7680 x 4320 image");
  return [o] { return runMpiBench(*o); };
}

}  // namespace pvrt::cli
