// `pvrt render SCENE -o OUT`: the paper's "input, output, optional saved configuration".
#include <csignal>
#include <chrono>
#include <cctype>
#include <cstdio>
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "cli/progress.h"
#include "core/atomic_file.h"
#include "core/error.h"
#include "image/image_io.h"
#include "render/renderer.h"
#include "scene/xml_loader.h"
#include "scene/xml_writer.h"

namespace pvrt::cli {

namespace {

std::atomic<bool> gInterrupted{false};
extern "C" void onInterrupt(int) { gInterrupted.store(true); }

struct RenderOptions {
  std::string scene, output, saveScene, samplerName = "pov", scheduleName, backendName = "openmp";
  int width = 0, height = 0, spp = 1, aaDepth = 0, threads = 0, chunk = 0, tileSize = 32;
  uint64_t seed = 0;
  bool stats = false, quiet = false;
};

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void printStats(const RenderOptions& o, const RenderSettings& s, const Scene& scene, const RenderResult& r,
                double loadS, double buildS, double writeS) {
  const RenderStats& t = r.totals;
  auto line = [](const char* what, uint64_t n) { fmt::print("  {:<22}{:>16}\n", what, n); };
  fmt::print("Render statistics\n");
  fmt::print("  Image                 {} x {}, {} rays/pixel ({} sampler, spp {})\n", s.width, s.height,
             PixelSampler(s.sampler).count(), samplerName(s.sampler.kind), s.sampler.samplesPerPixel);
  fmt::print("  Backend               {}, {} worker(s), schedule {}\n", o.backendName, r.workers.size(),
             strategyName(s.schedule.strategy));
  fmt::print("  Kernel effects        {}\n", effectNames(r.effects));
  fmt::print("  Objects               {} primitives, {} lights\n", scene.bvh.primitives().size(),
             scene.lights.size());
  line("Primary rays", t.primaryRays);
  line("Shadow rays", t.shadowRays);
  line("Reflected rays", t.reflectedRays);
  line("Refracted rays", t.refractedRays);
  line("Transmitted rays", t.transmittedRays);
  line("Total rays", t.totalRays());
  line("Intersection tests", t.intersectionTests);
  line("Shading operations", t.shadingOps);
  const BvhStats& b = scene.bvh.stats();
  fmt::print("  BVH                   {} nodes, {} leaves, depth {}, {:.1f} KiB, built in {:.4f} s\n", b.nodes,
             b.leaves, b.maxDepth, double(b.bytes) / 1024.0, b.buildSeconds);
  fmt::print("  Time                  load {:.4f} s, build {:.4f} s, render {:.4f} s, write {:.4f} s\n", loadS,
             buildS, r.seconds, writeS);
  fmt::print("  Rays per second       {:.0f}\n", r.seconds > 0 ? double(t.totalRays()) / r.seconds : 0.0);
  for (size_t w = 0; w < r.workers.size(); ++w) {
    const WorkerStats& ws = r.workers[w];
    fmt::print("  Worker {:<3}            {:>9} pixels, {:>12} rays, {:>14} work, {:.4f} s\n", w, ws.pixels,
               ws.counts.totalRays(), ws.counts.work(), ws.seconds);
  }
}

// Fails before any work is done when the output could not be written as asked.
void checkOutputFormat(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  for (char& ch : ext) ch = char(std::tolower(static_cast<unsigned char>(ch)));
  if (ext != ".png" && ext != ".tga" && ext != ".exr")
    throw Error(ExitCode::Usage, "cannot write \"" + path + "\": unsupported image format (use .png, .tga or .exr)");
  const auto dir = std::filesystem::path(path).parent_path();
  if (!dir.empty() && !std::filesystem::is_directory(dir))
    throw Error(ExitCode::OutputError, "cannot write \"" + path + "\": no such directory \"" + dir.string() + "\"");
}

int runRender(const RenderOptions& o) {
  checkOutputFormat(o.output);
  const auto t0 = Clock::now();
  SceneDesc desc = loadSceneFile(o.scene);
  const double loadS = since(t0);

  RenderSettings s;
  s.width = o.width > 0 ? o.width : (desc.image ? desc.image->width : 320);
  s.height = o.height > 0 ? o.height : (desc.image ? desc.image->height : 240);
  if (long(s.width) * s.height > (1L << 28))
    throw Error(ExitCode::Usage, fmt::format("image of {} x {} pixels is too large", s.width, s.height));
  s.sampler.kind = parseSamplerKind(o.samplerName);
  s.sampler.samplesPerPixel = o.aaDepth > 0 ? o.aaDepth * o.aaDepth : o.spp;
  s.sampler.seed = o.seed;
  PixelSampler check(s.sampler);  // validates spp before any work
  s.backend = o.backendName == "serial" ? Backend::Serial : Backend::OpenMP;
  s.threads = o.threads;
  if (!o.scheduleName.empty()) {
    s.schedule.strategy = parseStrategy(o.scheduleName);
  } else {
    scheduleFromEnvironment(s.schedule);  // OMP_SCHEDULE picks an OpenMP schedule
  }
  if (o.chunk > 0) s.schedule.chunk = o.chunk;
  s.schedule.tileSize = o.tileSize;
  s.cancel = &gInterrupted;

  if (!o.saveScene.empty()) {
    desc.image = ImageDesc{s.width, s.height, {}};
    writeFileAtomically(o.saveScene, sceneToXml(desc));
  }

  const auto t1 = Clock::now();
  const Scene scene = buildScene(desc);
  const double buildS = since(t1);

  ProgressBar bar(!o.quiet);
  s.progress = [&bar](long done, long total) { bar.update(done, total); };
  std::signal(SIGINT, onInterrupt);
  std::signal(SIGTERM, onInterrupt);
  const RenderResult r = render(scene, s);
  bar.finish();
  if (r.cancelled || gInterrupted) {
    std::fprintf(stderr, "pvrt: interrupted; nothing was written\n");
    return int(ExitCode::Interrupted);
  }
  const auto t2 = Clock::now();
  writeImage(r.image, o.output);
  const double writeS = since(t2);
  if (o.stats) printStats(o, s, scene, r, loadS, buildS, writeS);
  if (!o.quiet && !o.stats) fmt::print("wrote {} ({} x {}) in {:.3f} s\n", o.output, s.width, s.height, since(t0));
  return 0;
}

}  // namespace

Command addRenderCommand(CLI::App& app) {
  auto o = std::make_shared<RenderOptions>();
  CLI::App* c = app.add_subcommand("render", "Render an XML scene to an image (PNG, TGA or EXR)");
  c->add_option("scene", o->scene, "Scene file (XML)")->required();
  c->add_option("-o,--output", o->output, "Output image: .png, .tga (8-bit sRGB) or .exr (linear float)")
      ->required();
  c->add_option("-W,--width", o->width, "Image width (default: the scene's <image>, else 320)")
      ->check(CLI::Range(1, 65536));
  c->add_option("-H,--height", o->height, "Image height (default: the scene's <image>, else 240)")
      ->check(CLI::Range(1, 65536));
  c->add_option("--spp", o->spp, "Samples per pixel c, a perfect square; pov adds the centre ray (c=1: one ray)")
      ->check(CLI::Range(1, 1 << 16));
  c->add_option("--aa-depth", o->aaDepth, "POV-Ray's +R n: sets --spp to n*n")->check(CLI::Range(1, 9));
  c->add_option("--sampler", o->samplerName, "Sample pattern: pov, grid or jitter")->capture_default_str();
  c->add_option("--seed", o->seed, "Seed of the jitter sampler");
  c->add_option("--backend", o->backendName, "serial or openmp")
      ->check(CLI::IsMember({"serial", "openmp"}))
      ->capture_default_str();
  c->add_option("-t,--threads", o->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--schedule", o->scheduleName,
                "block, cyclic, static, dynamic, guided, runtime (OMP_SCHEDULE) or tiles (default: tiles, "
                "or OMP_SCHEDULE when set)");
  c->add_option("--chunk", o->chunk, "Chunk size in rows for static/dynamic/guided")->check(CLI::Range(1, 1 << 20));
  c->add_option("--tile-size", o->tileSize, "Tile side in pixels for --schedule tiles")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  c->add_option("--save-scene", o->saveScene, "Also write the scene as loaded (with the resolution used)");
  c->add_flag("--stats", o->stats, "Print render statistics (rays by kind, tests, effects, time)");
  c->add_flag("-q,--quiet", o->quiet, "No progress bar or summary line");
  return [o] { return runRender(*o); };
}

}  // namespace pvrt::cli
