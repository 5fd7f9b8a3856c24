// `pvrt compare A B [--diff D.png]`: how far apart two images are, in 8-bit levels.
#include <fmt/core.h>

#include <limits>
#include <string>

#include "cli/commands.h"
#include "core/error.h"
#include "core/error_line.h"
#include "core/output_files.h"
#include "image/compare.h"
#include "image/image_io.h"

namespace pvrt::cli {

namespace {

const CLI::Validator kShare = numberFrom(0, 1, "a share from 0 to 1", "0..1");

struct CompareOptions {
  std::string a, b, diff;
  CompareThresholds t;
  int diffScale = 16;
};

int runCompare(const CompareOptions& o) {
  // The difference image's path is checked before the images are read.
  OutputFiles out;
  // The difference image is a PNG: a name of another format is refused, as render refuses
  // -o x.bmp (it wrote PNG bytes to d.tga before); a pipe or /dev/stdout is written.
  if (!o.diff.empty() && imageFormatOf(o.diff) != ".png")
    throw Error(ExitCode::Usage, "cannot write \"" + printableName(o.diff) + "\": --diff writes a PNG (name it .png)");
  out.input(o.a);
  out.input(o.b);
  if (!o.diff.empty()) out.output(o.diff, "--diff");
  CompareResult r;
  try {
    r = compareFiles(o.a, o.b);
  } catch (const Error& e) {
    // An image that cannot be read ends compare with exit code 4, as an output that cannot
    // be written does, and its line reads the same: `pvrt: error: cannot read image ...`.
    fmt::print(stderr, "{}\n", errorLine(Error(ExitCode::OutputError, e.what())));
    return int(CompareExit::FileError);
  }
  if (r.sizeMismatch) {
    fmt::print("FAILURE: the images differ in size: \"{}\" is {} x {}, \"{}\" {} x {}\n", o.a, r.width, r.height,
               o.b, r.otherWidth, r.otherHeight);
    return int(CompareExit::Failure);
  }
  static const char* channel[] = {"R", "G", "B"};
  fmt::print("Comparing \"{}\" and \"{}\" ({} x {})\n", o.a, o.b, r.width, r.height);
  fmt::print("  Mean error = {:.6g} levels\n", r.meanError);
  fmt::print("  RMS error = {:.6g} levels\n", r.rmsError);
  fmt::print("  Peak SNR = {:.6g} dB\n", r.psnr);
  fmt::print("  Max error = {} levels @ ({}, {}, {})\n", r.maxError, r.maxX, r.maxY, channel[r.maxChannel % 3]);
  fmt::print("  {} channels: {} differ, {} by more than 1 level ({:.4f}%), {} by more than 2\n", r.channels, r.over0,
             r.over1, 100.0 * double(r.over1) / double(r.channels), r.over2);
  if (!o.diff.empty()) {
    writeDifferenceImage(o.a, o.b, out.stage(o.diff, ".png"), o.diffScale);
    out.commit();
  }
  if (r.over0 == 0) {
    fmt::print("PASS (identical)\n");
    return int(CompareExit::Pass);
  }
  if (r.pass(o.t)) {
    if (o.t.maxOffBy1 >= 0)
      fmt::print("PASS (within {} levels, at most {:.4f}% over 1 level, at most {} off by 1)\n", o.t.maxLevels,
                 o.t.maxFractionOver1 * 100, o.t.maxOffBy1);
    else
      fmt::print("PASS (within {} levels, at most {:.4f}% over 1 level)\n", o.t.maxLevels, o.t.maxFractionOver1 * 100);
    return int(CompareExit::Pass);
  }
  fmt::print("FAILURE\n");
  return int(CompareExit::Failure);
}

}  // namespace

Command addCompareCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  CLI::App* c =
      app.add_subcommand("compare",
                         "Compare two images pixel by pixel. Exit 0: PASS (identical or within the thresholds), "
                         "1: FAILURE (over the thresholds, or sizes differ), 2: bad command line, "
                         "4: an image cannot be read");
  c->add_option("a", o->a, "First image")->required();
  c->add_option("b", o->b, "Second image")->required();
  c->add_option("--diff", o->diff, "Write |A-B| x scale as a PNG");
  c->add_option("--diff-scale", o->diffScale, "Scale of the difference image")
      ->capture_default_str()
      ->check(CLI::Range(1, 255));
  c->add_option("--max-levels", o->t.maxLevels, "Largest allowed difference in levels")
      ->capture_default_str()
      ->check(CLI::Range(0, 255));
  c->add_option("--max-fraction-over-1", o->t.maxFractionOver1, "Allowed share of channels over 1 level")
      ->capture_default_str()
      ->check(kShare);
  c->add_option("--max-off-by-1", o->t.maxOffBy1, "Allowed count of channels that differ by exactly 1 level (-1: any)")
      ->capture_default_str()
      ->check(CLI::Range(-1L, std::numeric_limits<long>::max()));
  return [o] { return runCompare(*o); };
}

}  // namespace pvrt::cli
