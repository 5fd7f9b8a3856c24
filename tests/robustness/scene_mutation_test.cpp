// The mutation test: the repository's own scenes, mutated many times over (mutations.h),
// through the loader and the build stage in this process. Every mutant must either load or
// be refused with a pvrt::Error(SceneError) whose message is one `NAME:LINE: error: ` line;
// any other exception, a crash or a hang fails. Mutants that load are rendered at 8 x 8 in
// a child process (so a crash or a runaway render is caught and named) and every value of
// the float image must be finite.
//
//   scene_mutation_test SCENES_DIR [--mutants N] [--seed S] [--seconds T] [--save DIR]
//
// N mutants per scene (default 150, or $PVRT_MUTANTS); T bounds the wall time (default 40 s,
// or $PVRT_MUTATION_SECONDS; 0: no bound). Failing mutants are written to DIR to reproduce.
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "mutations.h"
#include "render/renderer.h"
#include "scene/xml_loader.h"

namespace fs = std::filesystem;
using namespace pvrt;

namespace {

char gCurrent[512] = "";  // the mutant being loaded, for the crash handler

extern "C" void onCrash(int sig) {
  const char msg[] = "\nscene_mutation_test: crashed (signal) while loading or building ";
  (void)!write(2, msg, sizeof msg - 1);
  (void)!write(2, gCurrent, strlen(gCurrent));
  (void)!write(2, "\n", 1);
  signal(sig, SIG_DFL);
  raise(sig);
}

struct Counts {
  long mutants = 0, refused = 0, loaded = 0, rendered = 0, slow = 0, overflowed = 0, failures = 0;
};
const std::string kInf = "the rendered image holds inf";

// Renders at 8 x 8 in a child; "" when fine or too slow (counted in `slow`), else why not.
std::string renderInChild(const Scene& scene, int timeoutSeconds, Counts& n) {
  const pid_t pid = fork();
  if (pid < 0) return "fork failed";
  if (pid == 0) {
    alarm(unsigned(timeoutSeconds));  // a runaway render (adc_bailout 0, deep glass) is not a bug
    RenderSettings s;
    s.width = s.height = 8;
    s.backend = Backend::Serial;
    s.threads = 1;
    const RenderResult r = render(scene, s);
    for (float v : r.image.data())
      if (std::isnan(v)) _exit(3);
    for (float v : r.image.data())
      if (std::isinf(v)) _exit(4);
    _exit(0);
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(status) && WTERMSIG(status) == SIGALRM) {
    std::printf("slow (not a failure): %s took more than %d s to render 8x8\n", gCurrent, timeoutSeconds);
    return ++n.slow, "";
  }
  if (WIFSIGNALED(status)) return std::string("render crashed with signal ") + strsignal(WTERMSIG(status));
  if (WEXITSTATUS(status) == 3) return "the rendered image holds NaN";
  if (WEXITSTATUS(status) == 4) return kInf;
  if (WEXITSTATUS(status) != 0) return "the render failed with exit status " + std::to_string(WEXITSTATUS(status));
  return ++n.rendered, "";
}

// Whether `text` holds a number above 1e3 in magnitude. Colours and coefficients above 1
// amplify light at every bounce, so such a scene may overflow the float range legally (a
// reflection of 65537 between glass spheres; POV-Ray's float colours overflow too), and an
// infinite pixel is accepted from it. NaN never is, nor inf from an ordinary scene.
bool hasHugeNumber(const std::string& text) {
  static const std::regex number("[0-9]*\\.?[0-9]+([eE][-+]?[0-9]+)?");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number); it != std::sregex_iterator(); ++it)
    if (std::fabs(std::strtod(it->str().c_str(), nullptr)) > 1e3) return true;
  return false;
}

// "" when the mutant loads (and renders) or is refused properly, else what went wrong.
std::string check(const std::string& name, const std::string& text, Counts& n) {
  Scene scene;
  try {
    scene = buildScene(loadSceneString(text, name));
  } catch (const Error& e) {
    const std::string m = e.what();
    static const std::regex form("[^\n]+:[0-9]+: error: [^\n]+");
    if (e.code() != ExitCode::SceneError) return "wrong exit code " + std::to_string(int(e.code())) + ": " + m;
    if (m.compare(0, name.size() + 1, name + ":") != 0 || !std::regex_match(m, form))
      return "message not of the form `" + name + ":LINE: error: ...`: " + m;
    return ++n.refused, "";
  } catch (const std::exception& e) {
    return std::string("not a pvrt::Error: ") + e.what();
  }
  ++n.loaded;
  const std::string why = renderInChild(scene, 5, n);
  if (why == kInf && hasHugeNumber(text)) return ++n.overflowed, "";
  return why;
}

long envOr(const char* name, long fallback) {
  const char* v = std::getenv(name);
  return v && *v ? std::atol(v) : fallback;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s SCENES_DIR [--mutants N] [--seed S] [--seconds T] [--save DIR]\n", argv[0]);
    return 2;
  }
  long mutants = envOr("PVRT_MUTANTS", 150), seconds = envOr("PVRT_MUTATION_SECONDS", 40);
  uint64_t seed = 1;
  std::string save = "mutation-failures";
  for (int i = 2; i + 1 < argc; i += 2) {
    const std::string opt = argv[i];
    if (opt == "--mutants") mutants = std::atol(argv[i + 1]);
    else if (opt == "--seed") seed = std::strtoull(argv[i + 1], nullptr, 10);
    else if (opt == "--seconds") seconds = std::atol(argv[i + 1]);
    else if (opt == "--save") save = argv[i + 1];
  }
  signal(SIGSEGV, onCrash);
  signal(SIGABRT, onCrash);
  signal(SIGFPE, onCrash);
  signal(SIGBUS, onCrash);

  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(argv[1]))
    if (e.path().extension() == ".xml") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  if (scenes.empty()) return std::fprintf(stderr, "no scenes in %s\n", argv[1]), 1;

  const auto start = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  Counts n;
  bool outOfTime = false;
  // Mutant i of every scene before mutant i+1 of any, so a time bound still covers all scenes.
  for (long i = 0; i < mutants && !outOfTime; ++i)
    for (size_t k = 0; k < scenes.size(); ++k) {
      if (seconds > 0 && elapsed() > double(seconds)) {
        outOfTime = true;
        break;
      }
      std::ifstream in(scenes[k], std::ios::binary);
      std::stringstream text;
      text << in.rdbuf();
      robustness::Rng rng(seed * 0x100000001b3ull ^ (uint64_t(k) << 32) ^ uint64_t(i));
      std::string what;
      const std::string mutant = robustness::mutate(text.str(), rng, what);
      const std::string name = scenes[k].stem().string() + ".m" + std::to_string(i) + ".xml";
      std::snprintf(gCurrent, sizeof gCurrent, "%s (%s)", name.c_str(), what.c_str());
      ++n.mutants;
      const std::string why = check(name, mutant, n);
      if (why.empty()) continue;
      ++n.failures;
      fs::create_directories(save);
      std::ofstream(fs::path(save) / name, std::ios::binary) << mutant;
      std::printf("FAIL %s (%s): %s [saved in %s]\n", name.c_str(), what.c_str(), why.c_str(), save.c_str());
    }
  std::printf("%ld mutants of %zu scenes (seed %llu) in %.1f s: %ld refused, %ld loaded, %ld rendered 8x8, "
              "%ld renders stopped after 5 s, %ld overflowed to inf from numbers above 1e3, %ld failures%s\n",
              n.mutants, scenes.size(), static_cast<unsigned long long>(seed), elapsed(), n.refused, n.loaded,
              n.rendered, n.slow, n.overflowed, n.failures, outOfTime ? " (stopped at the time bound)" : "");
  return n.failures == 0 ? 0 : 1;
}
