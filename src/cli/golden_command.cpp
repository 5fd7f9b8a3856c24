// `pvrt golden run|compare|make|bless|report`: image-regression tests of any folder of
// scenes against references (POV-Ray's renders, or pvrt's own blessed ones). A thin layer
// over src/golden; docs/golden.md says how to use it, docs/cli.md lists every option.
#include <filesystem>

#include <fmt/core.h>

#include "cli/commands.h"
#include "core/error.h"
#include "core/interrupt.h"
#include "core/output_files.h"
#include "golden/references.h"
#include "golden/report.h"
#include "golden/runner.h"

namespace pvrt::cli {

namespace {

namespace fs = std::filesystem;
using namespace pvrt::golden;

// A list option takes one value each time it is given (`--scene a --scene b`), so that it
// never swallows the positional folder after it (`--scene a SCENES`).
constexpr auto kEach = CLI::MultiOptionPolicy::TakeAll;

struct GoldenOptions {
  std::string scenes, references, images, report, junit;
  std::vector<std::string> names;  // positional scenes of make and bless
  RunOptions run;
  MakeOptions make;
  bool append = false, yes = false;
};

std::string referencesOf(const GoldenOptions& o) {
  return o.references.empty() ? o.scenes + "/reference" : o.references;
}

// Prints one line per test, writes the reports unless results are being gathered for later,
// and gives the exit code: 0 when every test passed, 1 otherwise.
int finish(const GoldenOptions& o, const std::vector<Outcome>& outcomes, const std::string& hint) {
  long failures = 0;
  for (const Outcome& x : outcomes) {
    failures += !x.passed;
    fmt::print("{} {}: {}\n", x.passed ? "PASS" : "FAIL", x.name, x.message);
  }
  fmt::print("{} tests, {} failed\n", outcomes.size(), failures);
  if (!o.append) {
    const std::string html = o.report.empty() ? o.run.out + "/report.html" : o.report;
    const std::string junit = o.junit.empty() ? o.run.out + "/junit.xml" : o.junit;
    ReportOptions r;
    r.hint = hint;
    writeHtmlReport(outcomes, html, r);
    writeJunit(outcomes, junit);
    fmt::print("JUnit XML: {}\nreport: {}\n", fs::absolute(junit).string(), fs::absolute(html).string());
  }
  return failures ? 1 : 0;
}

// A --report or --junit path that cannot be written fails now, naming it, rather than after
// every render, naming the report's scratch picture (`r.html.scratch.png`). The default ones
// are in --out, which the run makes first.
void checkReportPaths(const GoldenOptions& o) {
  OutputFiles probe;
  if (!o.report.empty()) probe.output(o.report, "--report");
  if (!o.junit.empty()) probe.output(o.junit, "--junit");
}

void clearResults(const GoldenOptions& o) {
  if (o.append) return;
  std::error_code ec;
  fs::remove_all(o.run.out + "/results", ec);
}

std::string hintFor(const GoldenOptions& o) {
  return fmt::format("If the new pictures are right, store them: pvrt golden bless {} SCENE... --references {} "
                     "(or remake POV-Ray's: pvrt golden make {} SCENE...).",
                     o.scenes, referencesOf(o), o.scenes);
}

int runGolden(const GoldenOptions& o) {
  const Suite suite = openSuite(o.scenes, referencesOf(o));
  checkReportPaths(o);
  clearResults(o);
  return finish(o, runSuite(suite, o.run), hintFor(o));
}

int compareGolden(const GoldenOptions& o) {
  const Suite suite = openSuite(o.scenes, referencesOf(o));
  checkReportPaths(o);
  clearResults(o);
  return finish(o, compareFolder(suite, o.images, o.run),
                "Images of " + o.images + " against the references of " + referencesOf(o) + ".");
}

int makeGolden(GoldenOptions o) {
  Suite suite = openSuite(o.scenes, referencesOf(o));
  o.make.scenes = o.names;
  const int failures = makeReferences(suite, o.make);
  return failures ? 1 : 0;
}

// Renders the chosen scenes with pvrt (serial), says how each differs from its reference,
// and stores the changed and new ones only with --yes.
int blessGolden(GoldenOptions o) {
  Suite suite = openSuite(o.scenes, referencesOf(o));
  checkReportPaths(o);
  Suite planned = suite;
  std::vector<ManifestEntry> entries;
  for (const std::string& scene : o.names.empty() ? suite.sceneNames : o.names) {
    if (!fs::exists(suite.scenePath(scene)))
      throw Error(ExitCode::Usage, "pvrt golden: error: no scene \"" + printableName(suite.scenePath(scene)) + "\"");
    for (const ManifestEntry& e : plannedEntries(suite, scene, o.make.variant, "", o.make.width)) planned.manifest.put(e);
  }
  o.run.scenes = o.names;
  if (!o.make.variant.empty()) o.run.variants = {o.make.variant};
  o.run.backends = {"serial"};
  o.run.ignoreStale = true;
  clearResults(o);
  const std::vector<Outcome> outcomes = runSuite(planned, o.run);
  std::vector<ManifestEntry> changed;
  std::vector<Outcome> changedOutcomes;
  bool renderFailed = false;
  for (const Outcome& x : outcomes) {
    const ManifestEntry* e = planned.manifest.find(x.scene, x.variant);
    const std::string name = x.scene + "." + x.variant;
    const bool existed = e && fs::exists(planned.referencePath(*e));
    if (x.image.empty()) {
      fmt::print("{}: {}\n", name, x.message);
      renderFailed = true;
      continue;
    }
    const CompareResult& r = x.stats;
    if (!existed) fmt::print("{}: new reference ({} x {})\n", name, e->width, e->height);
    else if (x.compared && !r.sizeMismatch && r.over0 == 0) {
      fmt::print("{}: unchanged (identical to {})\n", name, x.reference);
      continue;
    } else if (r.sizeMismatch) fmt::print("{}: changes: the size differs from {}\n", name, x.reference);
    else
      fmt::print("{}: changes: {} of {} channels differ, max {} levels at ({}, {}), {} by more than 1\n", name,
                 r.over0, r.channels, r.maxError, r.maxX, r.maxY, r.over1);
    changed.push_back(*e);
    changedOutcomes.push_back(x);
  }
  ReportOptions r;
  r.title = "pvrt golden bless: pvrt's renders against the references they would replace";
  const std::string html = o.report.empty() ? o.run.out + "/report.html" : o.report;
  writeHtmlReport(outcomes, html, r);
  fmt::print("report: {}\n", fs::absolute(html).string());
  if (renderFailed) {
    fmt::print("some renders failed: nothing stored\n");
    return 1;
  }
  if (changed.empty()) {
    fmt::print("nothing to bless: pvrt's renders are the references' pixels already\n");
    return 0;
  }
  if (!o.yes) {
    fmt::print("{} reference(s) would change; run again with --yes to store them\n", changed.size());
    return 0;
  }
  storeBlessed(suite, changed, changedOutcomes);
  fmt::print("stored {} reference(s) and {}\n", changed.size(), suite.manifestPath());
  return 0;
}

int reportGolden(const GoldenOptions& o) {
  const std::vector<Outcome> outcomes = loadOutcomes(o.run.out + "/results");
  long failures = 0;
  for (const Outcome& x : outcomes) failures += !x.passed;
  const std::string html = o.report.empty() ? o.run.out + "/report.html" : o.report;
  const std::string junit = o.junit.empty() ? o.run.out + "/junit.xml" : o.junit;
  ReportOptions r;
  r.hint = o.scenes.empty() ? "" : hintFor(o);
  writeHtmlReport(outcomes, html, r);
  writeJunit(outcomes, junit);
  for (const Outcome& x : outcomes)
    if (!x.passed) fmt::print("FAIL {}: {}\n", x.name, x.message.substr(0, x.message.find('\n')));
  fmt::print("{} tests, {} failed\nJUnit XML: {}\nreport: {}\n", outcomes.size(), failures,
             fs::absolute(junit).string(), fs::absolute(html).string());
  return failures ? 1 : 0;
}

void suiteOptions(CLI::App* c, GoldenOptions& o) {
  c->add_option("scenes", o.scenes, "Folder of XML scenes")->required();
  c->add_option("--references", o.references, "Folder of manifest.tsv, tolerances.tsv and the images (default SCENES/reference)");
}

void outputOptions(CLI::App* c, GoldenOptions& o) {
  c->add_option("--out", o.run.out, "Folder of the renders, logs, results and reports")->capture_default_str();
  c->add_option("--report", o.report, "The HTML report (default OUT/report.html)");
  c->add_option("--junit", o.junit, "The JUnit XML file (default OUT/junit.xml)");
}

void selectOptions(CLI::App* c, GoldenOptions& o) {
  c->add_option("--scene", o.run.scenes, "Only this scene (repeatable)")->expected(1)->multi_option_policy(kEach);
  c->add_option("--variant", o.run.variants, "Only this variant, e.g. aa or noaa (repeatable)")
      ->expected(1)->multi_option_policy(kEach);
  c->add_option("--skip-list", o.run.skipList, "File of scene.variant names to leave out, one a line");
  c->add_flag("--append", o.append, "Add to OUT/results and write no report (pvrt golden report OUT writes it)");
}

}  // namespace

Command addGoldenCommand(CLI::App& app) {
  auto o = std::make_shared<GoldenOptions>();
  CLI::App* g = app.add_subcommand("golden", "Image-regression tests of a folder of scenes against references "
                                             "(exit 0: all pass, 1: some failed)");
  g->require_subcommand(1);

  CLI::App* run = g->add_subcommand("run", "Render every reference's scene on each backend and compare");
  suiteOptions(run, *o);
  selectOptions(run, *o);
  outputOptions(run, *o);
  run->add_option("--backends", o->run.backends, "serial, openmp, mpi (comma-separated)")
      ->delimiter(',')->expected(1)->multi_option_policy(kEach)->capture_default_str();
  run->add_option("--threads", o->run.threads, "Threads of an openmp render")->check(CLI::Range(1, 1024))->capture_default_str();
  run->add_option("--np", o->run.ranks, "Ranks of an mpi render")->check(CLI::Range(1, 1024))->capture_default_str();
  run->add_option("-j,--jobs", o->run.jobs, "Renders at once (default half the CPUs)")->check(CLI::Range(1, 1024));
  run->add_option("--mpirun", o->run.mpirun, "mpirun to start mpi renders with")->capture_default_str();
  run->add_option("--render-option", o->run.renderOptions, "An option for every pvrt render, e.g. --render-option=--schedule=cyclic")
      ->expected(1)->multi_option_policy(kEach);

  CLI::App* cmp = g->add_subcommand("compare", "Compare another renderer's images with the references");
  suiteOptions(cmp, *o);
  selectOptions(cmp, *o);
  outputOptions(cmp, *o);
  cmp->add_option("--images", o->images, "Folder of images named as the references")->required();

  CLI::App* make = g->add_subcommand("make", "Make references with POV-Ray from each scene's export");
  suiteOptions(make, *o);
  make->add_option("scene", o->names, "Scenes to make (default all)");
  make->add_option("--variant", o->make.variant, "Only this variant (a new one is made with --antialiasing)");
  make->add_option("--antialiasing", o->make.antialiasing, "POV-Ray options, e.g. \"+A0.0 +AM1 +R3 -J\" (default: the manifest's)");
  make->add_option("--width", o->make.width, "Width of a new reference")->check(CLI::Range(1, 16384))->capture_default_str();
  make->add_option("--povray", o->make.povray, "POV-Ray program")->capture_default_str();
  make->add_option("-j,--jobs", o->make.jobs, "POV-Ray renders at once (default half the CPUs)")->check(CLI::Range(1, 1024));
  make->add_flag("--verify", o->make.verify, "Render again and check the stored pixels; store nothing");

  CLI::App* bless = g->add_subcommand("bless", "Keep pvrt's own renders as references (shows the changes; --yes stores)");
  suiteOptions(bless, *o);
  bless->add_option("scene", o->names, "Scenes to bless (default all)");
  bless->add_option("--variant", o->make.variant, "Only this variant");
  bless->add_option("--width", o->make.width, "Width of a new reference")->check(CLI::Range(1, 16384))->capture_default_str();
  bless->add_option("--out", o->run.out, "Folder of the renders and the report")->capture_default_str();
  bless->add_option("--report", o->report, "The HTML report (default OUT/report.html)");
  bless->add_flag("--yes", o->yes, "Store the changed and new references");

  CLI::App* report = g->add_subcommand("report", "Write the report of the results gathered in OUT with --append");
  report->add_option("out", o->run.out, "The --out folder of the runs")->required();
  report->add_option("--report", o->report, "The HTML report (default OUT/report.html)");
  report->add_option("--junit", o->junit, "The JUnit XML file (default OUT/junit.xml)");
  report->add_option("--scenes", o->scenes, "The scenes folder, for the report's hint");
  report->add_option("--references", o->references, "The references folder, for the report's hint");

  return [o, run, cmp, make, bless] {
    // Ctrl-C ends the renders and POV-Ray, then this run (130), removing its scratch
    // folder; references and the manifest are replaced together or not at all.
    interrupt::install(removeStagedFilesNow);
    if (run->parsed()) return runGolden(*o);
    if (cmp->parsed()) return compareGolden(*o);
    if (make->parsed()) return makeGolden(*o);
    if (bless->parsed()) return blessGolden(*o);
    return reportGolden(*o);
  };
}

}  // namespace pvrt::cli
