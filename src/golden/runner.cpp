#include "golden/runner.h"

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <set>
#include <thread>

#include <fmt/core.h>

#include "core/error.h"
#include "golden/process.h"
#include "golden/render_settings.h"
#include "golden/tsv.h"

namespace pvrt::golden {

namespace fs = std::filesystem;

namespace {

bool chosen(const std::vector<std::string>& list, const std::string& x) {
  return list.empty() || std::find(list.begin(), list.end(), x) != list.end();
}

// The command line of one render: the backend decides the program and its parallelism.
std::vector<std::string> renderCommand(const RunOptions& o, const std::string& backend, const std::string& scene,
                                       const std::string& image, const std::vector<std::string>& settings,
                                       const ManifestEntry& e) {
  using Args = std::vector<std::string>;
  const std::string pvrt = selfPath();
  Args argv;
  if (backend == "mpi") {
    argv = {o.mpirun};
    if (geteuid() == 0) argv.push_back("--allow-run-as-root");
    const Args mpi = {"--oversubscribe", "--bind-to", "none", "-np", std::to_string(o.ranks),
                      pvrt, "render", "--backend", "mpi", "--threads", "1"};
    argv.insert(argv.end(), mpi.begin(), mpi.end());
  } else if (backend == "openmp") {
    argv = {pvrt, "render", "--backend", "openmp", "--threads", std::to_string(o.threads)};
  } else {
    argv = {pvrt, "render", "--backend", "serial"};
  }
  const Args common = {scene, "-o", image, "-W", std::to_string(e.width), "-H", std::to_string(e.height), "--quiet"};
  for (const Args* more : {&common, &settings, &o.renderOptions}) argv.insert(argv.end(), more->begin(), more->end());
  return argv;
}

Outcome failed(const std::string& name, const std::string& scene, const std::string& variant,
               const std::string& backend, const std::string& message) {
  Outcome x;
  x.name = name;
  x.scene = scene;
  x.variant = variant;
  x.backend = backend;
  x.message = message;
  return x;
}

std::set<std::string> readSkipList(const std::string& path) {
  std::set<std::string> s;
  if (path.empty()) return s;
  for (const std::string& line : readLines(path, false))
    if (!line.empty()) s.insert(line);
  return s;
}

}  // namespace

int defaultJobs() { return std::max(1, int(std::thread::hardware_concurrency()) / 2); }

Selection select(const Suite& suite, const RunOptions& o) {
  const std::set<std::string> skip = readSkipList(o.skipList);
  Selection s;
  for (const ManifestEntry& e : suite.manifest.entries)
    if (chosen(o.scenes, e.scene) && chosen(o.variants, e.variant) && !skip.count(e.name())) s.entries.push_back(e);
  for (const std::string& scene : suite.sceneNames) {
    const bool referenced = std::any_of(suite.manifest.entries.begin(), suite.manifest.entries.end(),
                                        [&](const ManifestEntry& e) { return e.scene == scene; });
    if (!referenced && chosen(o.scenes, scene) && !skip.count(scene + ".aa")) s.unreferenced.push_back(scene);
  }
  for (const std::string& scene : o.scenes)
    if (!std::binary_search(suite.sceneNames.begin(), suite.sceneNames.end(), scene))
      throw Error(ExitCode::Usage, "pvrt golden: error: no scene \"" + printableName(suite.scenePath(scene)) + "\"");
  return s;
}

std::vector<Outcome> runSuite(const Suite& suite, const RunOptions& o) {
  for (const std::string& b : o.backends)
    if (b != "serial" && b != "openmp" && b != "mpi")
      throw Error(ExitCode::Usage, "pvrt golden: error: unknown backend \"" + printableName(b) +
                                       "\" (serial, openmp or mpi)");
  const bool mpi = std::find(o.backends.begin(), o.backends.end(), "mpi") != o.backends.end();
  if (mpi && findProgram(o.mpirun).empty())
    throw Error(ExitCode::Usage, "pvrt golden: error: backend mpi needs \"" + printableName(o.mpirun) +
                                     "\", which is not found (--mpirun PATH)");
  const Selection sel = select(suite, o);
  const std::string images = o.out + "/images", logs = o.out + "/logs", results = o.out + "/results";
  makeFolder(images);
  makeFolder(logs);

  std::vector<Outcome> outcomes;
  for (const std::string& scene : sel.unreferenced)
    outcomes.push_back(failed(scene + ".aa.reference", scene, "aa", "reference",
                              "no reference in " + suite.manifestPath() +
                                  ": make one with `pvrt golden make` (POV-Ray) or `pvrt golden bless` (pvrt)"));
  std::vector<Job> jobs;
  std::vector<Outcome> pending;
  for (const ManifestEntry& e : sel.entries) {
    const std::string scene = suite.scenePath(e.scene);
    std::string problem;
    std::vector<std::string> settings;
    try {
      if (!fs::exists(scene)) problem = "the manifest's scene " + scene + " does not exist";
      else if (!o.ignoreStale && exportSha256(scene) != e.sdlSha256)
        problem = fmt::format("reference is stale: the scene's export no longer hashes to the manifest's {} "
                              "({}:{}); remake it (`pvrt golden make`) or bless it",
                              e.sdlSha256.substr(0, 12), suite.manifestPath(), e.line);
      else settings = renderSettings(e, suite.manifestPath());
    } catch (const Error& err) {
      problem = err.what();
    }
    for (const std::string& backend : o.backends) {
      Outcome x = failed(e.name() + "." + backend, e.scene, e.variant, backend, problem);
      x.tolerance = suite.tolerances.of(e.scene, e.variant);
      x.reference = suite.referencePath(e);
      if (!problem.empty()) {
        outcomes.push_back(x);
        continue;
      }
      x.image = images + "/" + x.name + ".png";
      std::error_code ignored;
      fs::remove(x.image, ignored);  // a render that fails must not leave the last run's image to judge
      jobs.push_back({renderCommand(o, backend, scene, x.image, settings, e), logs + "/" + x.name + ".log", ""});
      pending.push_back(x);
    }
  }
  const std::vector<JobResult> done = runJobs(jobs, o.jobs > 0 ? o.jobs : defaultJobs());
  for (size_t i = 0; i < pending.size(); ++i) {
    Outcome& x = pending[i];
    x.seconds = done[i].seconds;
    if (done[i].exitCode != 0) {
      x.message = fmt::format("the render failed (exit code {}; {}):\n{}", done[i].exitCode, jobs[i].log,
                              tailOf(jobs[i].log));
      x.image.clear();
    } else {
      judge(x);
    }
    outcomes.push_back(x);
  }
  for (const Outcome& x : outcomes) saveOutcome(x, results);
  std::sort(outcomes.begin(), outcomes.end(), [](const Outcome& a, const Outcome& b) { return a.name < b.name; });
  return outcomes;
}

std::vector<Outcome> compareFolder(const Suite& suite, const std::string& images, const RunOptions& o) {
  std::error_code ec;
  if (!fs::is_directory(images, ec))
    throw Error(ExitCode::Usage, "pvrt golden: error: \"" + printableName(images) + "\" is not a folder of images");
  const Selection sel = select(suite, o);
  std::vector<Outcome> outcomes;
  for (const ManifestEntry& e : sel.entries) {
    Outcome x = failed(e.name() + ".external", e.scene, e.variant, "external", "");
    x.tolerance = suite.tolerances.of(e.scene, e.variant);
    x.reference = suite.referencePath(e);
    x.image = images + "/" + e.imageName();
    if (!fs::exists(x.image)) {
      x.message = "no image " + x.image + " to compare with " + x.reference;
      x.image.clear();
    } else {
      judge(x);
    }
    outcomes.push_back(x);
  }
  for (const Outcome& x : outcomes) saveOutcome(x, o.out + "/results");
  return outcomes;
}

}  // namespace pvrt::golden
