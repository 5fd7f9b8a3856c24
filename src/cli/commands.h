// The subcommands of the `pvrt` program. Each registers its options on the CLI11 app
// and returns the function that runs it (returning the process exit code).
#pragma once

#include <functional>

#include <CLI/CLI.hpp>

namespace pvrt::cli {

using Command = std::function<int()>;

Command addRenderCommand(CLI::App& app);
Command addGenerateCommand(CLI::App& app);
Command addExportCommand(CLI::App& app);
Command addCompareCommand(CLI::App& app);
Command addAccuracyCommand(CLI::App& app);
Command addMpiBenchCommand(CLI::App& app);
Command addGoldenCommand(CLI::App& app);

}  // namespace pvrt::cli
