// `pvrt generate`: the paper's random scenes of spheres and point lights, from a seed.
#include <cmath>

#include <fmt/core.h>

#include "cli/commands.h"
#include "core/output_files.h"
#include "core/error.h"
#include "generate/random_scene.h"
#include "scene/xml_attributes.h"
#include "scene/xml_writer.h"

namespace pvrt::cli {

namespace {

struct GenerateCliOptions {
  GenerateOptions g;
  bool radiusMinGiven = false, radiusMaxGiven = false;
  std::string output, preset;
  std::vector<double> sphereBox, lightBox, palette;
  bool noFloor = false;
};

// Every number the generator writes must be one its own loader reads (scene/xml_attributes.h):
// finite and at most 1e15 in magnitude. Refused here, before anything is written.
void checkNumbers(const char* option, const std::vector<double>& values) {
  for (double v : values)
    if (!std::isfinite(v) || std::fabs(v) > kMaxSceneNumber)
      throw Error(ExitCode::Usage, fmt::format("{} {} is out of range (a finite number of at most 1e15 in magnitude, "
                                               "as scenes allow)", option, v));
}

Vec3 lo(const std::vector<double>& b) { return {b[0], b[1], b[2]}; }
Vec3 hi(const std::vector<double>& b) { return {b[3], b[4], b[5]}; }

int runGenerate(GenerateCliOptions o) {
  OutputFiles out;  // checked before the scene is made
  out.output(o.output, "-o");
  GenerateOptions g = o.g;
  if (o.preset == "paper1") g = paperScene1();
  if (o.preset == "paper2") g = paperScene2();
  if (!o.preset.empty()) {  // explicit options still win over the preset
    g.seed = o.g.seed != GenerateOptions{}.seed ? o.g.seed : g.seed;
  } else {  // a radius not given keeps the spheres' share of the box (radiusScaleFor)
    const double scale = radiusScaleFor(g.spheres);
    if (!o.radiusMinGiven) g.radiusMin *= scale;
    if (!o.radiusMaxGiven) g.radiusMax *= scale;
  }
  if (!o.sphereBox.empty()) { g.sphereBoxLo = lo(o.sphereBox); g.sphereBoxHi = hi(o.sphereBox); }
  if (!o.lightBox.empty()) { g.lightBoxLo = lo(o.lightBox); g.lightBoxHi = hi(o.lightBox); }
  if (!o.palette.empty()) g.palette = {o.palette[0], o.palette[1], o.palette[2], o.palette[3]};
  if (o.noFloor) g.floor = false;
  checkNumbers("--sphere-box", o.sphereBox);
  checkNumbers("--light-box", o.lightBox);
  checkNumbers("--radius-min", {g.radiusMin});
  checkNumbers("--radius-max", {g.radiusMax});
  checkNumbers("--palette", o.palette);
  for (int axis = 0; axis < 3; ++axis)
    if (g.sphereBoxLo[axis] > g.sphereBoxHi[axis] || g.lightBoxLo[axis] > g.lightBoxHi[axis])
      throw Error(ExitCode::Usage, "a box's low corner must not exceed its high corner");
  const Palette& w = g.palette;
  if (!(w.matte >= 0 && w.shiny >= 0 && w.mirror >= 0 && w.glass >= 0 && w.matte + w.shiny + w.mirror + w.glass > 0))
    throw Error(ExitCode::Usage, "--palette weights must not be negative, and not all zero");
  out.stageBytes(o.output, sceneToXml(generateScene(g)));
  out.commit();
  return 0;
}

}  // namespace

Command addGenerateCommand(CLI::App& app) {
  auto o = std::make_shared<GenerateCliOptions>();
  CLI::App* c = app.add_subcommand("generate", "Write a random scene of spheres and point lights (paper section 2)");
  c->add_option("-o,--output", o->output, "Scene file to write (XML)")->required();
  c->add_option("--spheres", o->g.spheres, "Number of spheres")->check(CLI::Range(0, 100000000))->capture_default_str();
  c->add_option("--lights", o->g.lights, "Number of point lights")->check(CLI::Range(0, 1000))->capture_default_str();
  c->add_option("--seed", o->g.seed, "Random seed")->check(kSeed)->capture_default_str();
  c->add_option("--width", o->g.width, "Image width stored in the scene")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  c->add_option("--height", o->g.height, "Image height stored in the scene")
      ->check(CLI::Range(1, 65536))
      ->capture_default_str();
  c->add_option("--radius-min", o->g.radiusMin,
                "Smallest sphere radius (default 0.2, times (100/N)^(1/3) above N = 100 spheres)")
      ->check(kPositive)
      ->each([o](const std::string&) { o->radiusMinGiven = true; });
  c->add_option("--radius-max", o->g.radiusMax,
                "Largest sphere radius (default 0.8, times (100/N)^(1/3) above N = 100 spheres)")
      ->check(kPositive)
      ->each([o](const std::string&) { o->radiusMaxGiven = true; });
  c->add_option("--sphere-box", o->sphereBox, "Sphere centres' box: x0 y0 z0 x1 y1 z1")->expected(6);
  c->add_option("--light-box", o->lightBox, "Light positions' box: x0 y0 z0 x1 y1 z1")->expected(6);
  c->add_option("--palette", o->palette, "Weights of matte shiny mirror glass materials")->expected(4);
  c->add_flag("--no-floor", o->noFloor, "Leave out the checkered floor plane");
  c->add_option("--preset", o->preset, "Start from the paper's scene: paper1 or paper2")
      ->check(CLI::IsMember({"paper1", "paper2"}));
  return [o] { return runGenerate(*o); };
}

}  // namespace pvrt::cli
