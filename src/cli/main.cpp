// pvrt: render XML scenes the way POV-Ray 3.7 renders them. A thin layer over the
// library: parse the command line, run one subcommand, map errors to exit codes.
#include <cstdio>
#include <cstdlib>
#include <map>

#include "cli/commands.h"
#include "cli/huge_pages.h"
#include "core/error.h"
#include "core/error_line.h"
#include "parallel/threads.h"

int main(int argc, char** argv) {
  // Checked as --threads is, before anything starts threads: libgomp would try to start every
  // thread asked for (OMP_NUM_THREADS=100000 aborted inside it). Values libgomp itself finds
  // invalid ("0", "abc") also get its own warning, printed before main().
  if (pvrt::threadsFromEnvironment() < 0) {
    std::fprintf(stderr, "pvrt: error: OMP_NUM_THREADS=\"%s\" is not a number of threads from 1 to %d (as --threads)\n",
                 pvrt::printableName(std::getenv("OMP_NUM_THREADS")).c_str(), pvrt::kMaxThreads);
    return int(pvrt::ExitCode::Usage);
  }
  pvrt::cli::restartWithHugePages(argv);
  CLI::App app{"pvrt: a parallel ray tracer whose pictures match POV-Ray 3.7"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pvrt 0.1.0");
  // One line per error, like every other error pvrt prints.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "pvrt: " + std::string(e.what()) + " (see --help)\n";
  });
  std::map<const CLI::App*, pvrt::cli::Command> commands;
  auto add = [&](pvrt::cli::Command (*make)(CLI::App&)) {
    const size_t before = app.get_subcommands({}).size();
    pvrt::cli::Command c = make(app);
    commands[app.get_subcommands({})[before]] = std::move(c);
  };
  add(pvrt::cli::addRenderCommand);
  add(pvrt::cli::addGenerateCommand);
  add(pvrt::cli::addExportCommand);
  add(pvrt::cli::addCompareCommand);
  add(pvrt::cli::addAccuracyCommand);
  add(pvrt::cli::addMpiBenchCommand);
  add(pvrt::cli::addGoldenCommand);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : int(pvrt::ExitCode::Usage);
  }
  try {
    for (const CLI::App* sub : app.get_subcommands())
      return commands.at(sub)();
  } catch (const pvrt::Error& e) {
    std::fprintf(stderr, "%s\n", pvrt::errorLine(e).c_str());
    return int(e.code());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "pvrt: error: out of memory\n");
    return int(pvrt::ExitCode::Internal);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "pvrt: internal error: %s\n", e.what());
    return int(pvrt::ExitCode::Internal);
  }
  return 0;
}
