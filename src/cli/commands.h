// The subcommands of the `pvrt` program. Each registers its options on the CLI11 app
// and returns the function that runs it (returning the process exit code).
#pragma once

#include <charconv>
#include <cmath>
#include <cstdint>
#include <functional>
#include <string>
#include <system_error>

#include <CLI/CLI.hpp>

namespace pvrt::cli {

using Command = std::function<int()>;

// Whether all of `s` is one number, read into `v` (std::from_chars: no sign for an unsigned
// type, no spaces, nothing left over).
template <class T>
bool parsesWhole(const std::string& s, T& v) {
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  return !s.empty() && ec == std::errc() && end == s.data() + s.size();
}

// A seed: a whole number from 0 to 2^64 - 1, written in decimal digits. CLI11 alone read
// "-1" as 2^64 - 1 and any larger number as 2^64 - 1 too, so that different seeds a user
// gave silently made the same scene.
inline const CLI::Validator kSeed(
    [](std::string& s) -> std::string {
      uint64_t v = 0;
      if (!parsesWhole(s, v)) return "a seed is a whole number from 0 to 18446744073709551615, got " + s;
      return {};
    },
    "UINT");

// A positive number, said so (CLI::PositiveNumber names its range up to 1.8e308 in 309 digits).
inline const CLI::Validator kPositive(
    [](std::string& s) -> std::string {
      double v = 0;
      if (!parsesWhole(s, v) || !(v > 0) || !std::isfinite(v)) return "expected a positive number, got " + s;
      return {};
    },
    "POSITIVE");

// A number from `lo` to `hi`, NaN refused (CLI::Range lets it through: it is neither below nor
// above); `what` names the range in the message, "expected <what>, got <value>".
inline CLI::Validator numberFrom(double lo, double hi, const std::string& what, const std::string& range) {
  return CLI::Validator(
      [=](std::string& v) -> std::string {
        double x = 0;
        if (!parsesWhole(v, x) || !(x >= lo && x <= hi)) return "expected " + what + ", got " + v;
        return {};
      },
      range);
}

Command addRenderCommand(CLI::App& app);
Command addGenerateCommand(CLI::App& app);
Command addExportCommand(CLI::App& app);
Command addCompareCommand(CLI::App& app);
Command addAccuracyCommand(CLI::App& app);
Command addMpiBenchCommand(CLI::App& app);
Command addGoldenCommand(CLI::App& app);

}  // namespace pvrt::cli
