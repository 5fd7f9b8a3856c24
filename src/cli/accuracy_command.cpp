// `pvrt accuracy SCENE`: error against a converged render as the supersampling coefficient
// c, the sample pattern and the trace depth grow, with the time each setting took; and
// the paper's quality variant (figure 13), where c grows with the thread count P.
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>

#include <fmt/core.h>

#include "cli/commands.h"
#include "core/output_files.h"
#include "core/error.h"
#include "image/image_io.h"
#include "render/accuracy.h"
#include "render/renderer.h"
#include "scene/xml_loader.h"

#ifndef PVRT_TOOLS_DIR
#define PVRT_TOOLS_DIR "tools"
#endif

namespace pvrt::cli {

namespace {

struct AccuracyOptions {
  std::string scene, csv, plot, golden;
  int width = 0, height = 0, threads = 0;
  std::vector<int> sppList{1, 4, 16, 64, 256};
  // Sample patterns: the samplers, and POV-Ray's adaptive antialiasing (the pov sampler with
  // --aa-threshold, method 1 or 2).
  std::vector<std::string> samplers{"pov", "grid", "jitter", "adaptive1", "adaptive2"};
  double aaThreshold = 0.3;
  int maxDepth = -1;  // -1: the scene's max_trace_level; 0: no depth sweep
  int depthSpp = 16;
  std::string depthSampler = "pov";
  int referenceSpp = 1024;
  std::string referenceSampler = "jitter";
  bool qualityVariant = false;
  int c0 = 16, maxThreads = 0;
  std::string qualitySampler = "pov";
  uint64_t seed = 0;
};

// A pattern's settings at c samples per pixel: "adaptive1" and "adaptive2" are the pov
// sampler with POV-Ray's +A threshold and method 1 or 2.
SamplerSettings patternSettings(const std::string& name, int spp, uint64_t seed, double threshold) {
  SamplerSettings s;
  s.samplesPerPixel = spp;
  s.seed = seed;
  if (name == "adaptive1" || name == "adaptive2") {
    s.kind = SamplerKind::Pov;
    s.adaptive.threshold = threshold;
    s.adaptive.method = name == "adaptive1" ? 1 : 2;
  } else {
    s.kind = parseSamplerKind(name);  // throws on an unknown name
  }
  return s;
}
std::string patternName(const SamplerSettings& s) {
  if (s.adaptive.threshold > 0 || s.adaptive.method == 2) return "adaptive" + std::to_string(s.adaptive.method);
  return samplerName(s.kind);
}

struct Row {
  std::string mode;  // samples, depth or quality
  SamplerSettings sampler;
  int depth = 0, threads = 0, raysPerPixel = 0;
  double seconds = 0;
  RenderStats rays;
  ImageError error;
  std::optional<ImageError> golden;  // against the POV-Ray image, pov pattern only
};

// What every row shares: the scene, the image size and the references.
struct Setup {
  SceneDesc desc;
  RenderSettings base;
  Image reference;
  std::optional<std::vector<uint8_t>> golden;
  int sceneDepth = 5;
};

Row measure(const Setup& su, const std::string& mode, SamplerSettings sampler, int depth, int threads) {
  SceneDesc desc = su.desc;
  desc.globals.maxTraceLevel = depth;
  const Scene scene = buildScene(desc);
  RenderSettings s = su.base;
  s.sampler = sampler;
  if (threads > 0) s.threads = threads;
  const RenderResult r = render(scene, s);
  // Adaptive patterns trace as many rays as their decisions ask for: the mean is shown.
  const PixelSampler ps(sampler);
  const int raysPerPixel = ps.adaptive() ? int(std::lround(double(r.totals.primaryRays) / (double(s.width) * s.height)))
                                         : ps.count();
  Row row{mode, sampler, depth, int(r.workers.size()), raysPerPixel, r.seconds, r.totals, {}, {}};
  const std::vector<uint8_t> img = encodeSrgb8(r.image);
  row.error = imageError8(img, encodeSrgb8(su.reference));
  if (su.golden && patternName(sampler) == "pov") row.golden = imageError8(img, *su.golden);
  return row;
}

std::string num(double v, const char* fmtSpec = "{:.4g}") {
  return std::isinf(v) ? std::string("inf") : fmt::format(fmt::runtime(fmtSpec), v);
}

void printHeader(bool golden) {
  fmt::print("{:<8} {:<9} {:>6} {:>5} {:>7} {:>7} {:>10} {:>12} {:>8} {:>8} {:>9}", "mode", "sampler", "c", "depth",
             "threads", "rays/px", "time s", "rays", "RMSE", "PSNR dB", ">1 lvl %");
  if (golden) fmt::print(" {:>10} {:>10} {:>10}", "POV RMSE", "POV PSNR", "POV >1 %");
  fmt::print("\n");
}

void printRow(const Row& r) {
  fmt::print("{:<8} {:<9} {:>6} {:>5} {:>7} {:>7} {:>10.4f} {:>12} {:>8.3f} {:>8} {:>9.3f}", r.mode,
             patternName(r.sampler), r.sampler.samplesPerPixel, r.depth, r.threads, r.raysPerPixel, r.seconds,
             r.rays.totalRays(), r.error.rmse, num(r.error.psnr, "{:.2f}"), 100 * r.error.shareOver1);
  if (r.golden)
    fmt::print(" {:>10.3f} {:>10} {:>10.3f}", r.golden->rmse, num(r.golden->psnr, "{:.2f}"),
               100 * r.golden->shareOver1);
  fmt::print("\n");
  std::fflush(stdout);
}

std::string csvText(const std::vector<Row>& rows) {
  std::string out =
      "mode,sampler,spp,depth,threads,rays_per_pixel,seconds,primary_rays,shadow_rays,reflected_rays,"
      "refracted_rays,transmitted_rays,total_rays,rmse,psnr,share_over1,golden_rmse,golden_psnr,golden_share_over1\n";
  for (const Row& r : rows) {
    out += fmt::format("{},{},{},{},{},{},{:.6f},{},{},{},{},{},{},{:.6f},{},{:.6f}", r.mode,
                       patternName(r.sampler), r.sampler.samplesPerPixel, r.depth, r.threads, r.raysPerPixel,
                       r.seconds, r.rays.primaryRays, r.rays.shadowRays, r.rays.reflectedRays, r.rays.refractedRays,
                       r.rays.transmittedRays, r.rays.totalRays(), r.error.rmse, num(r.error.psnr, "{:.6f}"),
                       r.error.shareOver1);
    if (r.golden)
      out += fmt::format(",{:.6f},{},{:.6f}\n", r.golden->rmse, num(r.golden->psnr, "{:.6f}"), r.golden->shareOver1);
    else
      out += ",,,\n";
  }
  return out;
}

// The equal-time and equal-error readings of the sample-pattern curves (RMSE over time).
void printReadings(const std::vector<Row>& rows, const std::vector<std::string>& patterns) {
  std::vector<std::vector<CurvePoint>> curves;
  std::vector<std::string> names;
  for (const std::string& p : patterns) {
    std::vector<CurvePoint> c;
    for (const Row& r : rows)
      if (r.mode == "samples" && patternName(r.sampler) == p) c.push_back({r.seconds, r.error.rmse});
    if (!c.empty()) {
      curves.push_back(c);
      names.push_back(p);
    }
  }
  if (curves.size() < 2) return;
  const double t = commonTime(curves), e = commonError(curves);
  fmt::print("\nEqual time ({:.4f} s): RMSE", t);
  for (size_t i = 0; i < curves.size(); ++i) {
    const auto v = errorAtTime(curves[i], t);
    fmt::print("  {} {}", names[i], v ? fmt::format("{:.3f}", *v) : "n/a");
  }
  fmt::print("\nEqual error (RMSE {:.3f}): time", e);
  for (size_t i = 0; i < curves.size(); ++i) {
    const auto v = timeAtError(curves[i], e);
    fmt::print("  {} {}", names[i], v ? fmt::format("{:.4f} s", *v) : "n/a");
  }
  fmt::print("\n");
}

std::string shellQuote(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// A python 3 with matplotlib: $PVRT_PYTHON, else the system one (Debian's package), else python3.
std::string findPython() {
  if (const char* p = std::getenv("PVRT_PYTHON"); p && *p) return p;
  for (const char* candidate : {"/usr/bin/python3", "python3"})
    if (std::system(fmt::format("{} -c 'import matplotlib' >/dev/null 2>&1", candidate).c_str()) == 0)
      return candidate;
  throw Error(ExitCode::OutputError, "cannot plot: no python3 with matplotlib (tools/install-deps.sh installs it)");
}

// Runs the plot script on `csvPath`, drawing into `pngPath`; errors name `name`, the --plot path.
void plot(const std::string& python, const std::string& csvPath, const std::string& pngPath, const std::string& name,
          const std::string& title) {
  const char* env = std::getenv("PVRT_PLOT_ACCURACY");
  const std::string script = env && *env ? env : std::string(PVRT_TOOLS_DIR) + "/plot_accuracy.py";
  const std::string cmd = fmt::format("{} {} {} {} --title {}", python, shellQuote(script), shellQuote(csvPath),
                                      shellQuote(pngPath), shellQuote(title));
  if (std::system(cmd.c_str()) != 0)
    throw Error(ExitCode::OutputError, "cannot write \"" + printableName(name) + "\": the plot script failed");
}

int runAccuracy(const AccuracyOptions& o) {
  // Everything the command line says is checked before any work.
  auto sampler = [&](const std::string& kind, int spp) {
    SamplerSettings s{parseSamplerKind(kind), spp, o.seed};
    PixelSampler check(s);  // perfect squares only
    return s;
  };
  auto pattern = [&](const std::string& name, int spp) {
    if (name != "pov" && name != "grid" && name != "jitter" && name != "sequence" && name != "adaptive1" &&
        name != "adaptive2")
      throw Error(ExitCode::Usage,
                  "unknown sample pattern \"" + name + "\" (use pov, grid, jitter, sequence, adaptive1 or adaptive2)");
    SamplerSettings s = patternSettings(name, spp, o.seed, o.aaThreshold);
    PixelSampler check(s);
    return s;
  };
  // POV-Ray's method 2 goes at most +R9 deep: adaptive2 rows stop at c = 81.
  auto tried = [](const std::string& name, int c) { return name != "adaptive2" || c <= 81; };
  for (const std::string& k : o.samplers)
    for (int c : o.sppList)
      if (tried(k, c)) pattern(k, c);
  const SamplerSettings refSampler = sampler(o.referenceSampler, o.referenceSpp);
  const SamplerSettings depthSampler = sampler(o.depthSampler, o.depthSpp);
  sampler(o.qualitySampler, 1);
  if (!o.plot.empty() && std::filesystem::path(o.plot).extension() != ".png")
    throw Error(ExitCode::Usage, "--plot must name a .png file, got \"" + printableName(o.plot) + "\"");
  // The outputs, and the python that draws the plot, are checked before the renders.
  OutputFiles out;
  out.input(o.scene);
  if (!o.golden.empty()) out.input(o.golden);
  if (!o.csv.empty()) out.output(o.csv, "--csv");
  if (!o.plot.empty()) out.output(o.plot, "--plot");
  const std::string python = o.plot.empty() ? std::string() : findPython();

  Setup su;
  su.desc = loadSceneFile(o.scene);
  su.sceneDepth = su.desc.globals.maxTraceLevel;
  RenderSettings& b = su.base;
  b.width = o.width;
  b.height = o.height;
  if (!o.golden.empty()) {
    int gw = 0, gh = 0;
    su.golden = readImage8(o.golden, gw, gh);
    if (b.width == 0) b.width = gw;
    if (b.height == 0) b.height = gh;
    if (b.width != gw || b.height != gh)
      throw Error(ExitCode::Usage, fmt::format("--reference \"{}\" is {} x {}, the render would be {} x {}",
                                               o.golden, gw, gh, b.width, b.height));
  }
  // Default size: 320 wide with the scene's aspect ratio (320 x 200 for the paper's scenes).
  const int sw = su.desc.image ? su.desc.image->width : 320, sh = su.desc.image ? su.desc.image->height : 240;
  if (b.width == 0) b.width = b.height ? std::max(1, int(std::lround(double(b.height) * sw / sh))) : 320;
  if (b.height == 0) b.height = std::max(1, int(std::lround(double(b.width) * sh / sw)));
  b.threads = o.threads;

  fmt::print("pvrt accuracy: {} at {} x {}, reference {} c={} (max_trace_level {}){}\n", o.scene, b.width, b.height,
             o.referenceSampler, o.referenceSpp, su.sceneDepth,
             su.golden ? ", POV-Ray image " + o.golden + " for the pov rows" : "");
  {
    const Scene scene = buildScene(su.desc);
    RenderSettings s = b;
    s.sampler = refSampler;
    const RenderResult r = render(scene, s);
    su.reference = r.image;
    fmt::print("reference rendered in {:.3f} s ({} rays)\n\n", r.seconds, r.totals.totalRays());
  }

  std::vector<Row> rows;
  printHeader(su.golden.has_value());
  auto add = [&](Row r) {
    printRow(r);
    rows.push_back(std::move(r));
  };
  if (o.qualityVariant) {
    const int maxP = o.maxThreads > 0 ? o.maxThreads : threadBudget();
    for (int p = 1; p <= maxP; ++p) {
      const int c = nearestPerfectSquare(double(o.c0) * p);
      add(measure(su, "quality", sampler(o.qualitySampler, c), su.sceneDepth, p));
    }
  } else {
    for (const std::string& k : o.samplers)
      for (int c : o.sppList)
        if (tried(k, c)) add(measure(su, "samples", pattern(k, c), su.sceneDepth, 0));
    const int maxDepth = o.maxDepth >= 0 ? o.maxDepth : su.sceneDepth;
    for (int d = 1; d <= maxDepth; ++d) add(measure(su, "depth", depthSampler, d, 0));
    printReadings(rows, o.samplers);
  }

  const std::string csv = csvText(rows);
  if (!o.csv.empty()) out.stageBytes(o.csv, csv);
  if (!o.plot.empty()) {
    // The plot script reads the CSV from a private temporary and draws into the staged PNG.
    const std::string data =
        createTemporaryFile(std::filesystem::temp_directory_path().string(), "pvrt-accuracy", ".csv", o.plot);
    const std::unique_ptr<const char, void (*)(const char*)> remove(data.c_str(), [](const char* f) { ::unlink(f); });
    std::FILE* f = std::fopen(data.c_str(), "wb");
    const bool ok = f && std::fwrite(csv.data(), 1, csv.size(), f) == csv.size();
    if (!f || std::fclose(f) != 0 || !ok) throw Error(ExitCode::OutputError, "cannot write the plot's data: " + data);
    plot(python, data, out.stage(o.plot), o.plot, std::filesystem::path(o.scene).filename().string());
  }
  out.commit();
  return 0;
}

}  // namespace

Command addAccuracyCommand(CLI::App& app) {
  auto o = std::make_shared<AccuracyOptions>();
  CLI::App* c = app.add_subcommand(
      "accuracy",
      "Error against a converged render as samples per pixel, sample pattern and trace depth grow, with the time "
      "each took (or, with --quality-variant, as c grows with the thread count)");
  c->add_option("scene", o->scene, "Scene file (XML)")->required();
  c->add_option("-W,--width", o->width, "Image width (default: 320, or the --reference image's)")
      ->check(CLI::Range(1, 65536));
  c->add_option("-H,--height", o->height, "Image height (default: from the scene's aspect ratio)")
      ->check(CLI::Range(1, 65536));
  c->add_option("--spp-list", o->sppList, "Samples per pixel to try (perfect squares)")
      ->delimiter(',')
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  c->add_option("--samplers", o->samplers,
                "Sample patterns to try: pov, grid, jitter, adaptive1, adaptive2 (POV-Ray's +AM1 and +AM2 with "
                "--aa-threshold; adaptive2 up to c = 81, POV-Ray's +R9)")
      ->delimiter(',')
      ->capture_default_str();
  c->add_option("--aa-threshold", o->aaThreshold, "POV-Ray's +A threshold of the adaptive patterns")
      ->capture_default_str();
  c->add_option("--max-depth", o->maxDepth,
                "Trace depths 1..N (max_trace_level) to try; default the scene's max_trace_level, 0: none")
      ->check(CLI::Range(0, 256));
  c->add_option("--depth-spp", o->depthSpp, "Samples per pixel of the depth rows")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  c->add_option("--depth-sampler", o->depthSampler, "Sample pattern of the depth rows")->capture_default_str();
  c->add_option("--reference-spp", o->referenceSpp, "Samples per pixel of the converged reference")
      ->check(CLI::Range(1, 1 << 16))
      ->capture_default_str();
  c->add_option("--reference-sampler", o->referenceSampler, "Sample pattern of the reference: jitter or grid")
      ->capture_default_str();
  c->add_option("--reference", o->golden,
                "Also compare the pov rows with this image (POV-Ray's render, e.g. reference/paper1.png); the "
                "render takes its size");
  c->add_option("--seed", o->seed, "Seed of the jitter sampler")->check(kSeed);
  c->add_option("-t,--threads", o->threads, "Worker threads (default: OMP_NUM_THREADS or all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_flag("--quality-variant", o->qualityVariant,
              "The paper's figure 13 instead: P = 1..--max-threads threads with c = c0 x P (the nearest square)");
  c->add_option("--c0", o->c0, "Samples per pixel per thread of --quality-variant")
      ->check(CLI::Range(1, 4096))
      ->capture_default_str();
  c->add_option("--max-threads", o->maxThreads, "Largest P of --quality-variant (default: all cores)")
      ->check(CLI::Range(1, 1024));
  c->add_option("--quality-sampler", o->qualitySampler, "Sample pattern of --quality-variant")->capture_default_str();
  c->add_option("--csv", o->csv, "Also write the table as CSV");
  c->add_option("--plot", o->plot, "Plot error against time (log-log) to this PNG (python3 + matplotlib)");
  return [o] { return runAccuracy(*o); };
}

}  // namespace pvrt::cli
