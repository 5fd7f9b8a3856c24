#include "golden/references.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>

#include <fmt/core.h>

#include "core/error.h"
#include "core/output_files.h"
#include "golden/process.h"
#include "golden/render_settings.h"
#include "golden/runner.h"
#include "pov_export.h"
#include "scene/xml_loader.h"

namespace pvrt::golden {

namespace fs = std::filesystem;

namespace {

const char* kDefaultAntialiasing = "+A0.0 +AM1 +R3 -J";  // POV-Ray semantics section 0: the pov sampler's grid

std::string readBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::string povrayVersion(const std::string& povray, const std::string& work) {
  const std::string log = work + "/version.log";
  runJob({{povray, "--version"}, log, ""});
  std::smatch m;
  const std::string text = readBytes(log);
  return std::regex_search(text, m, std::regex("POV-Ray ([0-9][^ \\n]*)")) ? m[1].str() : "unknown";
}

// A scratch folder under /tmp: Debian's POV-Ray may only write below /tmp and its current folder.
struct WorkDir {
  std::string path;
  WorkDir() {
    char name[] = "/tmp/pvrt-golden.XXXXXX";
    if (!mkdtemp(name)) throw Error(ExitCode::OutputError, "pvrt golden: error: cannot make a folder in /tmp");
    path = name;
  }
  ~WorkDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

std::vector<ManifestEntry> plannedEntries(const Suite& suite, const std::string& scene, const std::string& variant,
                                          const std::string& antialiasing, int width) {
  std::vector<ManifestEntry> planned;
  for (const ManifestEntry& e : suite.manifest.entries)
    if (e.scene == scene && (variant.empty() || e.variant == variant)) planned.push_back(e);
  if (planned.empty()) {  // a new entry: the scene's other references' size, or the test width and its aspect
    const SceneDesc desc = loadSceneFile(suite.scenePath(scene));
    const ImageDesc image = desc.image.value_or(ImageDesc{});
    ManifestEntry e;
    e.scene = scene;
    e.variant = variant.empty() ? "aa" : variant;
    e.width = width;
    e.height = std::max(1, int((long(width) * image.height + image.width / 2) / image.width));
    for (const ManifestEntry& other : suite.manifest.entries)
      if (other.scene == scene) {
        e.width = other.width;
        e.height = other.height;
        break;
      }
    e.command = "povray +I" + scene + ".pov +O" + (e.variant == "aa" ? scene : scene + "." + e.variant) + ".png";
    planned.push_back(e);
  }
  if (planned.front().command.find("+FN") == std::string::npos) {  // new: POV-Ray's recipe, section 0
    ManifestEntry& e = planned.front();
    const std::string aa = antialiasing.empty() ? kDefaultAntialiasing : antialiasing;
    e.command = fmt::format("povray +I{}.pov +O{} +W{} +H{} -D +FN {}", e.scene, e.imageName(), e.width, e.height, aa);
    e.aaDepth = aaDepthOf(aa);
  }
  return planned;
}

int makeReferences(Suite& suite, const MakeOptions& o) {
  if (findProgram(o.povray).empty())
    throw Error(ExitCode::Usage, "pvrt golden: error: \"" + printableName(o.povray) +
                                     "\" not found: making references needs POV-Ray 3.7 (tools/install-deps.sh)");
  const std::vector<std::string> scenes = o.scenes.empty() ? suite.sceneNames : o.scenes;
  WorkDir work;
  const std::string version = povrayVersion(o.povray, work.path);
  std::vector<ManifestEntry> entries;
  std::vector<std::string> recorded;  // each entry's hash in the manifest (empty for a new one)
  std::vector<Job> jobs;
  for (const std::string& scene : scenes) {
    if (!fs::exists(suite.scenePath(scene)))
      throw Error(ExitCode::Usage, "pvrt golden: error: no scene \"" + printableName(suite.scenePath(scene)) + "\"");
    const PovExport pov = exportPov(loadSceneFile(suite.scenePath(scene)));
    if (!pov.warnings.empty())  // POV-Ray would render another scene: no reference is better than a wrong one
      throw Error(ExitCode::SceneError, pov.warnings.front() + " (a POV-Ray reference needs an exact export)");
    std::ofstream(work.path + "/" + scene + ".pov", std::ios::binary) << pov.sdl;
    for (ManifestEntry e : plannedEntries(suite, scene, o.variant, o.antialiasing, o.width)) {
      // An entry keeps its antialiasing unless told otherwise; a blessed one gets POV-Ray's recipe.
      std::string aa = o.antialiasing;
      if (aa.empty()) aa = e.blessed() ? kDefaultAntialiasing : povrayAntialiasing(e.command);
      e.command = fmt::format("povray +I{}.pov +O{} +W{} +H{} -D +FN {}", e.scene, e.imageName(), e.width, e.height, aa);
      e.aaDepth = aaDepthOf(aa);
      recorded.push_back(e.sdlSha256);
      e.sdlSha256 = sha256Hex(pov.sdl);
      e.renderer = version;
      std::vector<std::string> argv;
      std::istringstream words(e.command);
      for (std::string w; words >> w;) argv.push_back(w);
      argv[0] = o.povray;
      jobs.push_back({argv, work.path + "/" + e.name() + ".log", work.path});
      entries.push_back(e);
    }
  }
  const std::vector<JobResult> done = runJobs(jobs, o.jobs > 0 ? o.jobs : defaultJobs());
  int failures = 0;
  if (!o.verify) makeFolder(suite.references);  // a new suite's first references
  OutputFiles out;
  for (size_t i = 0; i < entries.size(); ++i) {
    const ManifestEntry& e = entries[i];
    const std::string made = work.path + "/" + e.imageName(), stored = suite.referencePath(e);
    if (done[i].exitCode != 0 || !fs::exists(made)) {
      fmt::print("{}: POV-Ray failed (exit code {}):\n{}", e.name(), done[i].exitCode, tailOf(jobs[i].log));
      ++failures;
      continue;
    }
    if (o.verify && recorded[i] != e.sdlSha256) {  // POV-Ray rendered another scene than the reference's
      fmt::print("{}: reference is stale: the scene's export no longer hashes to the manifest's {}, so POV-Ray "
                 "cannot reproduce it; remake it (`pvrt golden make`) or bless it\n",
                 e.name(), recorded[i].substr(0, 12));
      ++failures;
      continue;
    }
    if (o.verify) {  // the pixels, not the bytes: POV-Ray stamps the date in its PNGs
      const CompareResult r = compareFiles(made, stored);
      const bool same = !r.sizeMismatch && r.over0 == 0;
      fmt::print("{}: POV-Ray {} the reference ({} channels differ, max {} levels)\n", e.name(),
                 same ? "reproduces" : "does NOT reproduce", r.over0, r.maxError);
      failures += !same;
      continue;
    }
    out.output(stored, "reference");
    copyFile(made, out.stage(stored));
    suite.manifest.put(e);
    fmt::print("{}: {} x {}, {}\n", e.name(), e.width, e.height, e.command);
  }
  if (!o.verify && failures == 0) {
    out.output(suite.manifestPath(), "manifest");
    out.stageBytes(suite.manifestPath(), formatManifest(suite.manifest));
    out.commit();
    fmt::print("wrote {} reference{} and {}\n", entries.size(), entries.size() == 1 ? "" : "s", suite.manifestPath());
  } else if (!o.verify) {
    fmt::print("{} of {} reference{} failed: nothing stored\n", failures, entries.size(),
               entries.size() == 1 ? "" : "s");
  }
  return failures;
}

void storeBlessed(Suite& suite, const std::vector<ManifestEntry>& entries, const std::vector<Outcome>& outcomes) {
  makeFolder(suite.references);
  OutputFiles out;
  for (size_t i = 0; i < entries.size(); ++i) {
    ManifestEntry e = entries[i];
    const Outcome& x = outcomes[i];
    const std::string stored = suite.referencePath(e);
    out.output(stored, "reference");
    copyFile(x.image, out.stage(stored));
    std::string settings;
    for (const std::string& s : renderSettings(e, suite.manifestPath())) settings += " " + s;
    e.command = fmt::format("pvrt render {}.xml -o {} -W {} -H {}{}", e.scene, e.imageName(), e.width, e.height,
                            settings);
    e.renderer = "pvrt " PVRT_VERSION;
    e.sdlSha256 = exportSha256(suite.scenePath(e.scene));
    suite.manifest.put(e);
  }
  out.output(suite.manifestPath(), "manifest");
  out.stageBytes(suite.manifestPath(), formatManifest(suite.manifest));
  out.commit();
}

}  // namespace pvrt::golden
