// pvrt: render XML scenes the way POV-Ray 3.7 renders them. A thin layer over the
// library: parse the command line, run one subcommand, map errors to exit codes.
#include <cstdio>
#include <cstdlib>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cli/commands.h"
#include "cli/huge_pages.h"
#include "core/decimal_text.h"
#include "core/error.h"
#include "core/error_line.h"
#include "parallel/threads.h"

namespace {

// The commands `app` has, for messages: "render, generate, ...".
std::string commandNames(const CLI::App& app) {
  std::string names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names += (names.empty() ? "" : ", ") + sub->get_name();
  return names;
}

// Where `app` or one of its commands needs a command: the first word that names none, told as
// an unknown command with the ones there are, or the command line ending without one; nothing
// when every such word names one (options are left to CLI11).
std::optional<std::string> unknownCommand(const CLI::App& app, int argc, char** argv) {
  const CLI::App* at = &app;
  int i = 1;
  for (; i < argc && at->get_require_subcommand_min() > 0; ++i) {
    const std::string word = argv[i];
    if (word.empty() || word[0] == '-') return std::nullopt;
    const std::vector<const CLI::App*> next =
        at->get_subcommands([&](const CLI::App* sub) { return sub->check_name(word); });
    if (next.empty())
      return "unknown command \"" + pvrt::printableName(word) + "\" (the commands: " + commandNames(*at) + ")";
    at = next.front();
  }
  if (i == argc && at->get_require_subcommand_min() > 0)
    return (at == &app ? std::string() : at->get_name() + ": ") +
           "a command is required (the commands: " + commandNames(*at) + ")";
  return std::nullopt;
}

// Checks of every option of `app` and its commands, by its type, before the option's own
// (transform() puts them first). Numbers are read in decimal digits, as the scene format reads
// them (core/decimal_text.h): CLI11 reads integers with strtol in base 0 ("0x10" is 16, "010"
// is 8, " 8" is 8) and floats with strtold (hexadecimal, leading spaces); the option's range
// then reads the number as written.
void checkOptionValues(CLI::App& app) {
  const CLI::Validator whole(
      [](std::string& s) -> std::string {
        const std::optional<std::string> canonical = pvrt::canonicalWholeNumber(s);
        if (!canonical) return "expected a whole number in decimal digits, got \"" + pvrt::printableName(s) + "\"";
        s = *canonical;
        return {};
      },
      "");
  const CLI::Validator decimal(
      [](std::string& s) -> std::string {
        if (!pvrt::isDecimalNumber(s)) return "expected a decimal number, got \"" + pvrt::printableName(s) + "\"";
        if (s.front() == '+') s.erase(0, 1);  // the options' own checks read with from_chars, which takes no '+'
        return {};
      },
      "");
  // A name or word given empty (`--save-scene "$F"` with F unset) was taken as the option left
  // out, silently: no file written, the default schedule. `-o ""` already said so. (The golden
  // commands' options are folders and POV-Ray options, where empty has meanings of its own.)
  const CLI::Validator given(
      [](std::string& s) -> std::string {
        return s.empty() ? "the value is empty (give one, or leave the option out)" : "";
      },
      "");
  const CLI::Validator required([](std::string& s) -> std::string { return s.empty() ? "the value is empty" : ""; },
                                "");
  for (CLI::Option* option : app.get_options()) {
    if (option->get_type_size() == 0) continue;  // a flag
    const std::string type = option->get_type_name();
    const std::string base = type.substr(0, type.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZ"));
    if (base == "INT" || base == "UINT") option->transform(whole);
    else if (base == "FLOAT") option->transform(decimal);
    else if (base == "TEXT" && app.get_name() != "golden" &&
             (!app.get_parent() || app.get_parent()->get_name() != "golden"))
      option->transform(option->get_required() ? required : given);
  }
  for (CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) checkOptionValues(*sub);
}

}  // namespace

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
  pvrt::cli::keepHeapTop();
  CLI::App app{"pvrt: a parallel ray tracer whose pictures match POV-Ray 3.7"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "pvrt 0.1.0");
  // One line per error, like every other error pvrt prints.
  app.failure_message(
      [](const CLI::App*, const CLI::Error& e) { return "pvrt: error: " + std::string(e.what()) + " (see --help)\n"; });
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
  checkOptionValues(app);

  // A word where a command is required that names none (`pvrt rendr`, `pvrt golden rnu`) is
  // said to be one, rather than CLI11's "A subcommand is required".
  if (const std::optional<std::string> unknown = unknownCommand(app, argc, argv)) {
    std::fprintf(stderr, "pvrt: error: %s (see --help)\n", unknown->c_str());
    return int(pvrt::ExitCode::Usage);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = app.exit(e);
    return rc == 0 ? 0 : int(pvrt::ExitCode::Usage);
  }
  try {
    for (const CLI::App* sub : app.get_subcommands()) return commands.at(sub)();
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
