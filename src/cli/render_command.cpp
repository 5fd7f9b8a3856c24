// `pvrt render SCENE -o OUT`: the paper's "input, output, optional saved configuration".
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/progress.h"
#include "cli/stats_json.h"
#include "core/output_files.h"
#include "core/error.h"
#include "core/error_line.h"
#include "core/interrupt.h"
#include "core/memory_limit.h"
#include "image/image_io.h"
#include "image/load_map_picture.h"
#include "parallel/cluster.h"
#include "parallel/parallel_for.h"
#include "parallel/threads.h"
#include "render/distributed.h"
#include "render/renderer.h"
#include "render/render_region.h"
#include "render/passes.h"
#include "render/time_budget.h"
#include "cli/light_buffer_totals.h"
#include "core/memory_use.h"
#include "core/stage_clock.h"
#include "scene/xml_loader.h"
#include "scene/xml_writer.h"

namespace pvrt::cli {

namespace {

// --mpi-timeout's seconds (a NaN timeout would never end a job).
const CLI::Validator kTimeout = numberFrom(0, 1e6, "seconds from 0 to 1000000", "0..1e6");

// Ctrl-C and SIGTERM stop every stage within a fraction of a second (core/interrupt.h);
// nothing is written and pvrt exits with 130 (SIGINT) or 143 (SIGTERM).
// Under mpirun a rank ends at once on SIGINT, SIGTERM (what mpirun sends its ranks when it is
// interrupted) or SIGUSR1 (which mpirun forwards): rank 0 removes its temporaries and says
// so, and every rank exits with 130, which mpirun passes on as its own exit code when the
// signal came from SIGUSR1; on SIGINT and SIGTERM Open MPI's mpirun exits 1 whatever its
// ranks do (docs/cli.md).
int gRank = 0;
extern "C" void onMpiInterrupt(int) {
  removeStagedFilesNow();
  static const char msg[] = "pvrt: interrupted; nothing was written\n";
  if (gRank == 0) (void)!write(STDERR_FILENO, msg, sizeof msg - 1);
  // mpirun signals the ranks one after another, and once one has exited it SIGKILLs the
  // rest: rank 0, which holds the temporaries, could then be killed before its own SIGTERM
  // came (2 of 6 interrupts left a temporary). The other ranks let it go first.
  if (gRank != 0) {
    const timespec wait{0, 300 * 1000 * 1000};
    nanosleep(&wait, nullptr);
  }
  _exit(int(ExitCode::Interrupted));
}
void catchMpiInterrupts(int rank) {
  gRank = rank;
  struct sigaction sa {};
  sa.sa_handler = onMpiInterrupt;
  sigemptyset(&sa.sa_mask);
  for (int sig : {SIGINT, SIGTERM, SIGUSR1}) sigaction(sig, &sa, nullptr);
}
int interrupted() {
  std::fprintf(stderr, "%s\n", interrupt::error().what());
  return int(interrupt::exitCode());
}

struct RenderOptions {
  std::string scene, output, saveScene, samplerName = "pov", scheduleName, backendName = "openmp";
  std::string gatherName = "gather", loadMap, memoryLimit, statsJson;
  bool masterRenders = true;
  double mpiTimeout = 30;  // seconds a rank of the node may be stopped before the job ends
  int width = 0, height = 0, spp = 1, aaDepth = 0, threads = 0, chunk = 0, tileSize = 32;
  uint64_t seed = 0;
  AdaptiveSettings adaptive;  // --aa-threshold, --aa-method, --aa-block
  bool stats = false, quiet = false;
  bool hasTimeBudget = false;
  bool samplerGiven = false;  // --sampler was on the command line
  double timeBudget = 0;  // seconds, when hasTimeBudget
  RegionBounds region;    // POV-Ray's +SC/+EC/+SR/+ER
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// The NaN census (render/kernel_impl.h): on stderr whatever the options, since such
// pixels are not what the scene asked for.
void warnNonFinite(const RenderStats& t) {
  if (t.nonFiniteSamples || t.nonFinitePixels)
    std::fprintf(stderr,
                 "pvrt: warning: %llu samples were NaN or infinite and %llu pixels were affected or beyond "
                 "the range of a float (a NaN channel is written as 0, as POV-Ray writes it); a negative "
                 "colour raised to a reflection exponent gives NaN in POV-Ray too, otherwise please report "
                 "the scene\n",
                 (unsigned long long)t.nonFiniteSamples, (unsigned long long)t.nonFinitePixels);
}

void printStats(const RenderOptions& o, const RenderSettings& s, const Scene& scene, const RenderResult& r,
                const RunFigures& f, const std::vector<RankStats>& ranks = {}) {
  const RenderStats& t = r.totals;
  auto line = [](const char* what, uint64_t n) { fmt::print("  {:<22}{:>16}\n", what, n); };
  fmt::print("Render statistics\n");
  const PixelSampler sampler(s.sampler);
  if (sampler.adaptive()) {
    const AdaptiveSettings& a = sampler.adaptiveSettings();
    fmt::print("  Image                 {} x {}, POV-Ray's +A{} +AM{} +R{} +BS{} -J (pov sampler, spp {})\n",
               s.width, s.height, a.threshold, a.method, sampler.depth(), a.blockSize, s.sampler.samplesPerPixel);
  } else {
    fmt::print("  Image                 {} x {}, {} rays/pixel ({} sampler, spp {})\n", s.width, s.height,
               sampler.count(), samplerName(s.sampler.kind), s.sampler.samplesPerPixel);
  }
  if (s.region)
    fmt::print("  Region                columns {}-{}, rows {}-{} ({} x {})\n", s.region->x0 + 1, s.region->x1,
               s.region->y0 + 1, s.region->y1, s.region->x1 - s.region->x0, s.region->y1 - s.region->y0);
  if (ranks.empty()) {
    fmt::print("  Backend               {}, {} worker(s), schedule {}\n", o.backendName, r.workers.size(),
               strategyName(s.schedule.strategy));
  } else {
    // Threads per rank: one number when all ranks have the same, else each rank's.
    std::string threads = std::to_string(ranks[0].threads.size());
    bool same = true;
    for (const RankStats& k : ranks) same = same && k.threads.size() == ranks[0].threads.size();
    for (size_t i = 1; !same && i < ranks.size(); ++i) threads += "," + std::to_string(ranks[i].threads.size());
    fmt::print("  Backend               mpi, {} rank(s) x {} thread(s), schedule {}\n", ranks.size(), threads,
               strategyName(s.schedule.strategy));
  }
  fmt::print("  Kernel effects        {}\n", effectNames(r.effects));
  fmt::print("  Objects               {} primitives, {} lights\n", scene.bvh.size(),
             scene.lights.size());
  line("Primary rays", t.primaryRays);
  line("  of them, by vista", t.vistaRays);
  line("Shadow rays", t.shadowRays);
  line("Reflected rays", t.reflectedRays);
  line("Refracted rays", t.refractedRays);
  line("Transmitted rays", t.transmittedRays);
  line("Total rays", t.totalRays());
  line("Intersection tests", t.intersectionTests);
  line("Shading operations", t.shadingOps);
  line("Non-finite samples", t.nonFiniteSamples);
  line("Non-finite pixels", t.nonFinitePixels);
  fmt::print("  Length unit           {:g} (typical object size {:g})\n", scene.tol.unit, scene.tol.typicalSize);
  const BvhStats& b = scene.bvh.stats();
  fmt::print("  BVH                   {} nodes, {} leaves, depth {}, {:.1f} KiB, built in {:.4f} s\n", b.nodes,
             b.leaves, b.maxDepth, double(b.bytes) / 1024.0, b.buildSeconds);
  if (b.leafSize > kBvhLeafSize)
    fmt::print("  BVH leaves            up to {} primitives (a cheaper tree, for the memory limit of {}){}\n",
               b.leafSize, formatBytes(scene.memoryLimit),
               b.bytes > scene.memoryLimit ? "; still over it: the primitives alone take more" : "");
  const auto [buffers, entries, bytes, cells] = lightBufferTotals(scene);
  if (buffers > 0)
    fmt::print("  Light buffers         {} (up to {}x{} cells a face), {} entries, {:.1f} KiB ({:.0f} bytes a "
               "buffer), built in {:.4f} s\n",
               buffers, cells, cells, entries, double(bytes) / 1024.0, double(bytes) / double(buffers),
               scene.lightBufferSeconds);
  if (scene.lightsOverMemoryLimit > 0)
    fmt::print("  Memory limit          {}{}: {} light(s) left without a buffer\n", formatBytes(scene.memoryLimit),
               scene.memoryLimitScaled ? " (the BVH and 4 times it for light buffers; --memory-limit sets it)" : "",
               scene.lightsOverMemoryLimit);
  fmt::print("  Time                  load {:.4f} s, build {:.4f} s, render {:.4f} s, write {:.4f} s\n", f.load.wall,
             f.build.wall, f.render.wall, f.write.wall);
  // CPU / wall: the cores each stage kept busy (a serial stage stays near 1).
  fmt::print("  CPU time              load {:.3f} s ({:.2f} cores), build {:.3f} s ({:.2f}), render {:.3f} s ({:.2f}), "
             "write {:.3f} s ({:.2f}){}\n",
             f.load.cpu, f.load.cores(), f.build.cpu, f.build.cores(), f.render.cpu, f.render.cores(), f.write.cpu,
             f.write.cores(), ranks.empty() ? "" : ", rank 0");
  fmt::print("  Rays per second       {:.0f}\n", r.seconds > 0 ? double(t.totalRays()) / r.seconds : 0.0);
  const auto mib = [](size_t bytes) { return double(bytes) / double(1 << 20); };
  fmt::print("  Peak memory           {:.1f} MiB (after load {:.1f}, after build {:.1f}){}\n",
             mib(peakResidentBytes()), mib(f.loadPeakBytes), mib(f.buildPeakBytes), ranks.empty() ? "" : ", rank 0");
  if (!ranks.empty()) {
    fmt::print("  Gather                {}\n", o.gatherName);
    fmt::print("  MPI transports        {}\n", cluster::transports());
    fmt::print("  {:<6}{:>7}{:>10}{:>16}{:>11}{:>10}{:>10}{:>10}{:>12}\n", "Rank", "items", "pixels", "work",
               "compute s", "comm s", "idle s", "wall s", "sent KiB");
    double maxC = 0, sumC = 0, maxW = 0, sumW = 0;
    for (size_t i = 0; i < ranks.size(); ++i) {
      const RankStats& k = ranks[i];
      fmt::print("  {:<6}{:>7}{:>10}{:>16}{:>11.4f}{:>10.4f}{:>10.4f}{:>10.4f}{:>12.1f}\n", i, k.items, k.pixels,
                 k.counts.work(), k.computeSeconds, k.commSeconds, k.idleSeconds, k.wallSeconds,
                 k.bytesSent / 1024.0);
      if (k.threads.size() > 1)
        for (size_t t = 0; t < k.threads.size(); ++t)
          fmt::print("    thread {:<3}{:>13}{:>16}{:>11.4f}\n", t, k.threads[t].pixels, k.threads[t].counts.work(),
                     k.threads[t].seconds);
      maxC = std::max(maxC, k.computeSeconds);
      sumC += k.computeSeconds;
      maxW = std::max(maxW, double(k.counts.work()));
      sumW += double(k.counts.work());
    }
    const double nr = double(ranks.size());
    // Ranks that render nothing (a pure dynamic master) are left out of the means.
    double active = 0;
    for (const RankStats& k : ranks) active += k.pixels > 0 ? 1 : 0;
    fmt::print("  Imbalance (max/mean)  work {:.3f}, compute time {:.3f} over {} rendering rank(s) of {}\n",
               sumW > 0 ? maxW / (sumW / active) : 0.0, sumC > 0 ? maxC / (sumC / active) : 0.0, active, nr);
    return;
  }
  for (size_t w = 0; w < r.workers.size(); ++w) {
    const WorkerStats& ws = r.workers[w];
    fmt::print("  Worker {:<3}            {:>9} pixels, {:>12} rays, {:>14} work, {:.4f} s\n", w, ws.pixels,
               ws.counts.totalRays(), ws.counts.work(), ws.seconds);
  }
}

// The load map: linear work counts in an EXR, and a log-scale false-colour PNG with a
// colour bar (image/load_map_picture.h), as the paper's figures show it.
void stageLoadMap(OutputFiles& out, const std::string& prefix, const std::vector<float>& load, int width,
                  int height) {
  Image raw(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) raw.set(x, y, Color(load[size_t(y) * width + x]));
  writeImageFile(raw, out.stage(prefix + ".exr"), ".exr", prefix + ".exr");
  writeImageFile(loadMapPicture(load, width, height), out.stage(prefix + ".png"), ".png", prefix + ".png");
}

// The image in the format of `-o` (imageFormatOf: "-" is standard output, as PNG).
void stageImage(OutputFiles& out, const std::string& path, const Image& image) {
  const std::string format = imageFormatOf(path);
  writeImageFile(image, out.stage(path, format), format, path);
}

// Plans every output of the run and checks it before any work is done: formats, folders,
// no output that is the scene, no two outputs on one file (core/output_files.h).
void planOutputs(const RenderOptions& o, OutputFiles& out) {
  // A scene that cannot be opened at all is the first thing to say (read errors of other
  // kinds come from the loader).
  if (::access(o.scene.c_str(), R_OK) != 0)
    throw sceneFileError(o.scene, std::string("cannot read scene: ") + std::strerror(errno));
  out.input(o.scene);
  out.output(o.output, "-o");
  imageFormatOf(o.output);
  if (!o.loadMap.empty()) {
    out.output(o.loadMap + ".exr", "--load-map");
    out.output(o.loadMap + ".png", "--load-map");
  }
  if (!o.saveScene.empty()) out.output(o.saveScene, "--save-scene");
  if (!o.statsJson.empty()) out.output(o.statsJson, "--stats-json");
}

// --stats-json: staged with the other outputs, so that all or none of them appear.
void stageStatsJson(OutputFiles& out, const RenderOptions& o, const RenderSettings& s, const Scene& scene,
                    const RenderResult& r, RunFigures run, const std::vector<RankStats>& ranks = {}) {
  if (o.statsJson.empty()) return;
  run.scene = o.scene;
  run.output = o.output;
  run.backend = o.backendName;
  run.gather = o.gatherName;
  run.peakBytes = peakResidentBytes();
  out.stageBytes(o.statsJson, statsJson(run, s, scene, r, ranks));
}

// The sampler's name: --time-budget without --sampler takes sequence, whose c is any whole
// number (pov's squares jump from 16 to 25: 56% more rays) and whose image can be rendered
// in passes that stop when the budget is spent (render/passes.h). Not when adaptive
// antialiasing, which is pov's, was asked for.
std::string budgetSamplerName(const RenderOptions& o) {
  const bool adaptive = o.adaptive.threshold > 0 || o.adaptive.method != 1;
  return o.hasTimeBudget && !o.samplerGiven && !adaptive ? "sequence" : o.samplerName;
}

// Everything up to a built scene; local to each process (and to each MPI rank).
struct Prepared {
  SceneDesc desc;
  RenderSettings settings;
  Scene scene;
  StageTime load, build;
  size_t loadPeak = 0, buildPeak = 0;  // peak resident bytes at the end of each stage
  std::string savedScene;  // --save-scene's bytes, written with the image
};

// `writes`: this process writes the outputs (not the other MPI ranks).
Prepared prepare(const RenderOptions& o, bool writes) {
  imageFormatOf(o.output);
  if (o.hasTimeBudget && !(o.timeBudget > 0 && std::isfinite(o.timeBudget)))
    throw Error(ExitCode::Usage,
                fmt::format("--time-budget must be a positive number of seconds, got {}", o.timeBudget));
  if (o.hasTimeBudget && o.backendName == "mpi")
    throw Error(ExitCode::Usage, "--time-budget is not available with --backend mpi");
  if (o.threads > 0) setThreadBudget(o.threads);  // every stage, not only the render
  BuildOptions build;
  if (!o.memoryLimit.empty()) {
    build.memoryLimit = parseMemorySize(o.memoryLimit);
    build.memoryLimitGiven = true;
  }
  Prepared p;
  const StageClock loading;
  p.desc = loadSceneFile(o.scene);
  p.load = loading.elapsed();
  p.loadPeak = peakResidentBytes();

  RenderSettings& s = p.settings;
  s.width = o.width > 0 ? o.width : (p.desc.image ? p.desc.image->width : 320);
  s.height = o.height > 0 ? o.height : (p.desc.image ? p.desc.image->height : 240);
  if (static_cast<long long>(s.width) * s.height > ImageDesc::kMaxPixels)
    throw Error(ExitCode::Usage, fmt::format("pvrt: error: image of {} x {} pixels is more than {}", s.width,
                                             s.height, ImageDesc::kMaxPixels));
  if (o.region.any()) s.region = parseRegion(o.region, s.width, s.height);
  s.sampler.kind = parseSamplerKind(budgetSamplerName(o));
  s.sampler.samplesPerPixel = o.aaDepth > 0 ? o.aaDepth * o.aaDepth : o.spp;
  s.sampler.seed = o.seed;
  s.sampler.adaptive = o.adaptive;
  PixelSampler check(s.sampler);  // validates spp and the antialiasing before any work
  // POV-Ray's +A t (or +AM2) alone samples up to +R3; pvrt's --spp defaults to 1, where the
  // threshold and the method change nothing (-A). Say so rather than render without them.
  if (writes && !o.hasTimeBudget && s.sampler.samplesPerPixel == 1 &&
      (o.adaptive.threshold > 0 || o.adaptive.method == 2)) {
    const std::string given = o.adaptive.threshold > 0 ? fmt::format("--aa-threshold {}", o.adaptive.threshold)
                                                       : std::string("--aa-method 2");
    std::fprintf(stderr,
                 "pvrt: warning: %s does nothing at --spp 1 (one ray a pixel, POV-Ray's -A); POV-Ray's +A "
                 "alone supersamples with +R3, which is --spp 9\n",
                 given.c_str());
  }
  if (check.adaptive() && !o.loadMap.empty())
    throw Error(ExitCode::Usage,
                "--load-map is not available with --aa-threshold, --aa-method 2 or --pov-blocks (a pixel's rays "
                "are traced while its neighbours are)");
  // POV-Ray's adaptive decisions follow its 32-pixel blocks of the whole image, which a region
  // would cut elsewhere: the region's pixels would not be the full image's.
  if ((check.adaptive() || check.blockCache()) && s.region)
    throw Error(ExitCode::Usage,
                "a render region (--start-col ... --end-row) is not available with --aa-threshold, "
                "--aa-method 2 or --pov-blocks (they follow POV-Ray's blocks of the whole image)");
  s.backend = o.backendName == "serial" ? Backend::Serial : Backend::OpenMP;
  s.threads = o.threads;
  if (!o.scheduleName.empty()) {
    s.schedule.strategy = parseStrategy(o.scheduleName);
  } else if (o.backendName == "mpi") {
    // Ranks share tiles on demand: the only strategy that keeps ranks on CPUs of unequal
    // speed busy to the end (docs/parallel.md); OMP_SCHEDULE names OpenMP's schedules.
    s.schedule.strategy = Strategy::Dynamic;
  } else {
    scheduleFromEnvironment(s.schedule);  // OMP_SCHEDULE picks an OpenMP schedule
  }
  if (o.chunk > 0) s.schedule.chunk = o.chunk;
  s.schedule.tileSize = o.tileSize;
  s.loadMap = !o.loadMap.empty();
  if (!o.saveScene.empty() && writes) {  // kept until the image is done: nothing on disk before
    SceneDesc copy = p.desc;
    copy.image = ImageDesc{s.width, s.height, {}};
    p.savedScene = sceneToXml(copy);
  }
  const StageClock building;
  p.scene = buildScene(std::move(p.desc), build);  // frees the objects' descriptions early
  p.build = building.elapsed();
  p.buildPeak = peakResidentBytes();
  return p;
}

// `render`: the CPU time around the render; its wall time is the renderer's own.
RunFigures stageFigures(const Prepared& p, const RenderResult& r, double renderCpu, StageTime write,
                        const BudgetPlan* budget) {
  RunFigures f;
  f.load = p.load;
  f.build = p.build;
  f.render = {r.seconds, renderCpu};
  f.write = write;
  f.loadPeakBytes = p.loadPeak;
  f.buildPeakBytes = p.buildPeak;
  f.budget = budget;
  return f;
}

// "3.2 hours", "12 minutes", "40 seconds".
std::string roughly(double seconds) {
  if (seconds >= 2 * 86400) return fmt::format("{:.1f} days", seconds / 86400);
  if (seconds >= 2 * 3600) return fmt::format("{:.1f} hours", seconds / 3600);
  if (seconds >= 120) return fmt::format("{:.0f} minutes", seconds / 60);
  return fmt::format("{:.0f} seconds", seconds);
}

// A render predicted to take an hour or more says so on stderr, once, even with --quiet
// (PVRT_ANNOUNCE_SECONDS, for tests, sets another threshold).
void announceLongRenders(RenderSettings& s) {
  if (const char* v = std::getenv("PVRT_ANNOUNCE_SECONDS"); v && std::atof(v) > 0) s.announceSeconds = std::atof(v);
  s.announce = [](const LongRender& r) {
    const std::string what = r.atLeast ? "at least " + roughly(r.predictedSeconds)
                                       : "about " + roughly(r.predictedSeconds);
    std::fprintf(stderr, "\npvrt: this render will take %s (%.1f%% of the pixels done in %s); Ctrl-C stops it\n",
                 what.c_str(), 100 * r.shareDone, roughly(r.elapsedSeconds).c_str());
  };
}

// What writing the image is foreseen to take, for a time budget: 50 ns a pixel (a 1280 x 800
// PNG took 0.04-0.06 s on the 2-core VM, with 1 and 2 threads).
double foreseenWriteSeconds(const RenderSettings& s) { return 5e-8 * double(renderArea(s).pixels()); }

int runLocal(const RenderOptions& o) {
  const auto start = Clock::now();
  // Caught from the start: an interrupt while a big scene loads or builds ends it too. A
  // second signal ends the process at once, removing the temporaries first.
  interrupt::install(removeStagedFilesNow);
  OutputFiles out;
  planOutputs(o, out);
  Prepared p = prepare(o, true);
  if (interrupt::requested()) return interrupted();
  std::optional<BudgetPlan> budget;
  const bool inPasses = o.hasTimeBudget && p.settings.sampler.kind == SamplerKind::Sequence;
  if (inPasses) {
    // The budget is the whole run's: what loading and building took is spent already.
    PassBudget plan{o.timeBudget, since(start), foreseenWriteSeconds(p.settings), 1 << 16};
    p.settings.sampler.samplesPerPixel = plan.maxSamples;
    p.settings.nextPass = [plan](const PassesSoFar& so) { return nextPassEnd(plan, so); };
  } else if (o.hasTimeBudget) {
    // The budget is the whole run's: what loading and building took is spent already.
    const BudgetPlan& plan = budget.emplace(planForBudget(p.scene, p.settings, o.timeBudget, since(start)));
    p.settings.sampler.samplesPerPixel = plan.samplesPerPixel;
    if (!o.quiet) {
      std::string pilots;
      for (size_t i = 0; i < plan.pilotSamples.size(); ++i)
        pilots += fmt::format("{}c={}: {:.3g} s/pixel", i ? ", " : "", plan.pilotSamples[i],
                              plan.points[i].secondsPerPixel);
      fmt::print("time budget {:.3g} s: {} pilot(s) on {:.1f}% of the pixels took {:.3f} s ({}); chose --spp {} "
                 "--sampler {} (predicted render {:.3f} s{})\n",
                 o.timeBudget, plan.pilotSamples.size(), 100 * plan.pilotShare, plan.pilotSeconds, pilots,
                 plan.samplesPerPixel, samplerName(p.settings.sampler.kind), plan.predictedSeconds,
                 plan.fits ? "" : ", over the budget even at c=1");
    }
  }
  announceLongRenders(p.settings);
  const RenderSettings& s = p.settings;
  ProgressBar bar(!o.quiet);
  p.settings.progress = [&bar](long done, long total) { bar.update(done, total); };
  const double renderCpu0 = processCpuSeconds();
  const RenderResult r = render(p.scene, s);
  const double renderCpu = processCpuSeconds() - renderCpu0;
  bar.finish();
  if (r.cancelled || interrupt::requested()) return interrupted();
  if (inPasses) {
    p.settings.sampler.samplesPerPixel = r.passes.back().last;
    if (!o.quiet)
      fmt::print("time budget {:.3g} s: {} passes of the sequence sampler reached --spp {} (render {:.3f} s{})\n",
                 o.timeBudget, r.passes.size(), r.passes.back().last, r.seconds,
                 r.passes.size() == 1 && since(start) > o.timeBudget ? ", over the budget even at c=1" : "");
  }
  // From here on an interrupt lets the (atomic) write finish: the image is complete.
  const StageClock writing;
  stageImage(out, o.output, r.image);
  if (!o.loadMap.empty()) stageLoadMap(out, o.loadMap, r.load, r.image.width(), r.image.height());
  if (!o.saveScene.empty()) out.stageBytes(o.saveScene, p.savedScene);
  const StageTime write = writing.elapsed();  // encoding; the commit renames
  RunFigures figures = stageFigures(p, r, renderCpu, write, budget ? &*budget : nullptr);
  figures.timeBudget = o.hasTimeBudget ? o.timeBudget : 0;
  stageStatsJson(out, o, s, p.scene, r, figures);
  out.commit();
  warnNonFinite(r.totals);
  if (o.stats) printStats(o, s, p.scene, r, figures);
  if (!o.quiet && !o.stats)
    fmt::print("wrote {} ({} x {}) in {:.3f} s\n", o.output, r.image.width(), r.image.height(), since(start));
  return 0;
}

// Testing aids for the MPI backend, read from the environment of every rank:
//   PVRT_FAIL_RANK=r        rank r fails while loading, as with a bad scene
//   PVRT_SLOW_RANK=r:ms     rank r sleeps ms milliseconds per work item
int envInt(const char* name, int fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atoi(v) : fallback;
}

int runMpi(const RenderOptions& o) {
  cluster::Session session;
  const int me = cluster::rank();
  // The ranks of a node that may run on the same CPUs divide them: without --threads each
  // takes its share (at least one), and where they all fit each is kept to a run of CPUs
  // of its own, so no rank's threads ever compete with another's.
  catchMpiInterrupts(me);
  cluster::startWatchdog(o.mpiTimeout);
  const cluster::NodePlace place = cluster::placeOnNode(allowedCpus());
  setCpuShare({place.slot, place.slots});
  if (o.threads > 0) setThreadBudget(o.threads);
  pinProcessToShare();
  // Stage 1, local to each rank: anything may fail. Then every rank learns whether any
  // did, so all stop together with the first message, printed once, instead of hanging.
  std::optional<Prepared> p;
  std::optional<OutputFiles> out;  // rank 0's, which writes them
  std::string failure;
  try {
    if (me == 0) planOutputs(o, out.emplace());
    p.emplace(prepare(o, me == 0));
    if (envInt("PVRT_FAIL_RANK", -1) == me)
      throw Error(ExitCode::SceneError, fmt::format("rank {}: injected failure (PVRT_FAIL_RANK)", me));
  } catch (const Error& e) {
    failure = std::to_string(int(e.code())) + "|" + errorLine(e);
  } catch (const std::exception& e) {
    failure = std::to_string(int(ExitCode::Internal)) + "|pvrt: rank " + std::to_string(me) + ": " + e.what();
  }
  const std::string first = cluster::firstError(failure);
  if (!first.empty()) {
    const size_t bar = first.find('|');
    if (me == 0) std::fprintf(stderr, "%s\n", first.c_str() + bar + 1);
    return std::atoi(first.c_str());
  }

  DistributedSettings d;
  d.gather = parseGather(o.gatherName);
  d.masterRenders = o.masterRenders;
  d.eightBit = isEightBitFormat(imageFormatOf(o.output));
  if (const char* slow = std::getenv("PVRT_SLOW_RANK"); slow && std::strchr(slow, ':')) {
    d.slowRank = std::atoi(slow);
    d.slowMillis = std::atoi(std::strchr(slow, ':') + 1);
  }
  // Stage 2, collective: a failure here (out of memory) can only end the whole job.
  DistributedResult r;
  double renderCpu = 0;  // this rank's, communication included
  try {
    const double cpu0 = processCpuSeconds();
    r = renderDistributed(p->scene, p->settings, d);
    renderCpu = processCpuSeconds() - cpu0;
  } catch (const Error& e) {
    std::fprintf(stderr, "%s\n", errorLine(e).c_str());
    removeStagedFilesNow();  // the abort runs no destructors
    cluster::abortAll(int(e.code()));
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pvrt: rank %d: %s\n", me, e.what());
    removeStagedFilesNow();
    cluster::abortAll(int(ExitCode::Internal));
  }
  if (me != 0) {  // only rank 0 writes
    releaseIdleThreads();
    return 0;
  }
  // The node's other ranks have sent their last pixels and wait in MPI_Finalize (asleep, not
  // spinning), their threads ended: the encoding takes their CPUs too. 16 ranks of one thread
  // wrote paper1's 1280x800 PNG in 50-70 ms, one process of 16 threads in 8-15 ms.
  takeWholeShare();
  const RenderSettings& s = p->settings;
  const StageClock writing;
  if (d.eightBit) {
    const std::string format = imageFormatOf(o.output);
    writeImageFile8(r.rgb8, r.width, r.height, out->stage(o.output, format), format, o.output);
  } else {
    stageImage(*out, o.output, r.render.image);
  }
  if (!o.loadMap.empty()) stageLoadMap(*out, o.loadMap, r.render.load, r.width, r.height);
  if (!o.saveScene.empty()) out->stageBytes(o.saveScene, p->savedScene);
  // The write stage is the encoding; the commit renames.
  const RunFigures figures = stageFigures(*p, r.render, renderCpu, writing.elapsed(), nullptr);
  stageStatsJson(*out, o, s, p->scene, r.render, figures, r.ranks);
  out->commit();
  warnNonFinite(r.render.totals);
  if (o.stats) printStats(o, s, p->scene, r.render, figures, r.ranks);
  if (!o.quiet && !o.stats)
    fmt::print("wrote {} ({} x {}) with {} ranks in {:.3f} s\n", o.output, r.width, r.height, cluster::size(),
               r.render.seconds);
  return 0;
}

int runRender(const RenderOptions& o) { return o.backendName == "mpi" ? runMpi(o) : runLocal(o); }

}  // namespace

Command addRenderCommand(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* c = app.add_subcommand("render", "Render an XML scene to an image (PNG, TGA or EXR)");
  c->add_option("scene", o->scene, "Scene file (XML)")->required();
  c->add_option("-o,--output", o->output,
                "Output image: .png, .tga (8-bit sRGB) or .exr (linear float); - for standard output (PNG)")
      ->required();
  c->add_option("-W,--width", o->width, "Image width (default: the scene's <image>, else 320)")
      ->check(CLI::Range(1, 65536));
  c->add_option("-H,--height", o->height, "Image height (default: the scene's <image>, else 240)")
      ->check(CLI::Range(1, 65536));
  CLI::Option* spp =
      c->add_option("--spp", o->spp,
                    "Samples per pixel c: any c for jitter and sequence, a perfect square for pov and grid; pov adds "
                    "the centre ray (c=1: one ray)")
          ->check(CLI::Range(1, 1 << 16));
  CLI::Option* aa = c->add_option("--aa-depth", o->aaDepth, "POV-Ray's +R n: sets --spp to n*n")->check(CLI::Range(1, 9));
  CLI::Option* budget =
      c->add_option("--time-budget", o->timeBudget,
                    "Render for about SECONDS in all: with the sequence sampler (its default) in passes of more "
                    "samples, stopped when the next would not fit (any c); with pov and grid (squares) or "
                    "jitter, the largest --spp that pilots on 1/17 of the pixels predict to fit")
          ->excludes(spp)
          ->excludes(aa);
  CLI::Option* sampler =
      c->add_option("--sampler", o->samplerName,
                    "Sample pattern: pov, grid, jitter or sequence (with --time-budget the default is sequence)")
          ->capture_default_str();
  c->add_option("--aa-threshold", o->adaptive.threshold,
                "POV-Ray's +A t (pov sampler): supersample only the pixels whose colour differs from a neighbour's "
                "by t or more (0: every pixel)")
      ->capture_default_str();
  c->add_option("--aa-method", o->adaptive.method,
                "POV-Ray's +AM: 1, a pixel's centre ray plus its n x n grid where needed; 2, adaptive subdivision "
                "from the pixel corners, up to n - 1 levels (--spp n*n is +Rn)")
      ->capture_default_str();
  c->add_option("--aa-block", o->adaptive.blockSize,
                "POV-Ray's +BS: the render block size, which decides the result of --aa-threshold with method 1")
      ->capture_default_str();
  c->add_flag("--pov-blocks", o->adaptive.blocks,
              "Trace --aa-threshold 0 (+A0.0) in POV-Ray's order: block by block (--aa-block), each block's row "
              "above and column left first, the shadow cache kept within a block (closer to POV-Ray where a shadow "
              "edge crosses pixels; default: pixel by pixel)");
  c->add_option("--seed", o->seed, "Seed of the jitter and sequence samplers")->check(kSeed);
  c->add_option("--backend", o->backendName, "serial, openmp or mpi (start with mpirun; OpenMP threads in each rank)")
      ->check(CLI::IsMember({"serial", "openmp", "mpi"}))
      ->capture_default_str();
  c->add_option("-t,--threads", o->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--schedule", o->scheduleName,
                "block, cyclic, static, dynamic, guided, runtime (OMP_SCHEDULE) or tiles (default: tiles, "
                "or OMP_SCHEDULE when set; with --backend mpi: block, cyclic, tiles or dynamic, default dynamic)");
  c->add_option("--chunk", o->chunk, "Chunk size in rows for static/dynamic/guided")->check(CLI::Range(1, 1 << 20));
  c->add_option("--tile-size", o->tileSize, "Tile side in pixels for --schedule tiles")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  c->add_option("--gather", o->gatherName, "MPI: gather (MPI_Gatherv) or recursive-doubling")
      ->check(CLI::IsMember({"gather", "recursive-doubling"}))
      ->capture_default_str();
  c->add_flag("--master-renders,!--no-master-renders", o->masterRenders,
              "MPI dynamic: rank 0 renders tiles too, answering requests between them (the default); "
              "--no-master-renders keeps it to answering");
  c->add_option("--mpi-timeout", o->mpiTimeout,
                "MPI: end the job (exit 75) when a rank has been stopped (SIGSTOP) this many seconds (other nodes: "
                "when its heartbeats stop) "
                "(0: never)")
      ->check(kTimeout)
      ->capture_default_str();
  c->add_option("--start-col", o->region.startCol,
                "Render only from this column (POV-Ray's +SC): a pixel number from 1, or a share 0.0-1.0; the "
                "output holds the region alone");
  c->add_option("--end-col", o->region.endCol, "... to this column, included (+EC)");
  c->add_option("--start-row", o->region.startRow, "... from this row (+SR)");
  c->add_option("--end-row", o->region.endRow, "... to this row, included (+ER)");
  c->add_option("--load-map", o->loadMap,
                "Write the work per pixel to PREFIX.exr (counts) and PREFIX.png (log-scale false colour)");
  c->add_option("--save-scene", o->saveScene, "Also write the scene as loaded (with the resolution used)");
  c->add_option("--memory-limit", o->memoryLimit,
                "Memory for the acceleration structures, e.g. 2G or 512M (default: a quarter of the machine's "
                "memory, and for light buffers at most 4 times the BVH's, at least 64M); lights beyond it go "
                "without a light buffer (the same image, rendered slower or faster)");
  c->add_flag("--stats", o->stats, "Print render statistics (rays by kind, tests, effects, time)");
  c->add_option("--stats-json", o->statsJson,
                "Write every figure of --stats to FILE as JSON (written with the image; - for standard output)");
  c->add_flag("-q,--quiet", o->quiet, "No progress bar or summary line");
  return [o, budget, sampler] {
    o->hasTimeBudget = budget->count() > 0;
    o->samplerGiven = sampler->count() > 0;
    return runRender(*o);
  };
}

}  // namespace pvrt::cli
