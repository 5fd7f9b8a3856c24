#include "golden/outcome.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>

#include <fmt/core.h>

#include "core/error.h"
#include "golden/suite.h"
#include "golden/tsv.h"

namespace pvrt::golden {

namespace fs = std::filesystem;

namespace {

// Values are one line each: messages keep their line breaks as \n.
std::string flatten(std::string s) {
  std::string out;
  for (char c : s) out += c == '\n' ? std::string("\\n") : c == '\\' ? std::string("\\\\") : std::string(1, c);
  return out;
}

std::string unflatten(const std::string& s) {
  std::string out;
  for (size_t i = 0; i < s.size(); ++i) {
    if (s[i] == '\\' && i + 1 < s.size()) {
      out += s[i + 1] == 'n' ? '\n' : s[i + 1];
      ++i;
    } else {
      out += s[i];
    }
  }
  return out;
}

}  // namespace

void saveOutcome(const Outcome& o, const std::string& resultsDir) {
  makeFolder(resultsDir);
  const CompareResult& r = o.stats;
  std::map<std::string, std::string> kv = {
      {"name", o.name}, {"scene", o.scene}, {"variant", o.variant}, {"backend", o.backend},
      {"passed", o.passed ? "1" : "0"}, {"message", o.message}, {"compared", o.compared ? "1" : "0"},
      {"width", std::to_string(r.width)}, {"height", std::to_string(r.height)},
      {"mean", fmt::format("{}", r.meanError)}, {"rms", fmt::format("{}", r.rmsError)},
      {"psnr", fmt::format("{}", r.psnr)}, {"max", std::to_string(r.maxError)},
      {"max_x", std::to_string(r.maxX)}, {"max_y", std::to_string(r.maxY)},
      {"channels", std::to_string(r.channels)}, {"over0", std::to_string(r.over0)},
      {"over1", std::to_string(r.over1)}, {"over2", std::to_string(r.over2)},
      {"size_mismatch", r.sizeMismatch ? "1" : "0"},
      {"max_levels", std::to_string(o.tolerance.limits.maxLevels)},
      {"max_fraction_over_1", fmt::format("{}", o.tolerance.limits.maxFractionOver1)},
      {"max_off_by_1", std::to_string(o.tolerance.limits.maxOffBy1)},
      {"reason", o.tolerance.reason}, {"origin", o.tolerance.origin},
      {"image", o.image}, {"reference", o.reference}, {"seconds", fmt::format("{:.3f}", o.seconds)}};
  const std::string path = resultsDir + "/" + o.name + ".tsv", tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    for (const auto& [k, v] : kv) out << k << '\t' << flatten(v) << '\n';
    if (!out) throw Error(ExitCode::OutputError, "cannot write \"" + printableName(tmp) + "\"");
  }
  renameFile(tmp, path);  // a report never reads half a record
}

std::vector<Outcome> loadOutcomes(const std::string& resultsDir) {
  std::vector<Outcome> all;
  std::error_code ec;
  for (const fs::directory_entry& f : fs::directory_iterator(resultsDir, ec)) {
    if (f.path().extension() != ".tsv") continue;
    std::map<std::string, std::string> kv;
    for (const std::string& line : readLines(f.path().string(), false)) {
      const size_t tab = line.find('\t');
      if (tab != std::string::npos) kv[line.substr(0, tab)] = unflatten(line.substr(tab + 1));
    }
    auto num = [&](const char* k) { return kv.count(k) ? std::atof(kv[k].c_str()) : 0.0; };
    Outcome o;
    o.name = kv["name"];
    o.scene = kv["scene"];
    o.variant = kv["variant"];
    o.backend = kv["backend"];
    o.passed = kv["passed"] == "1";
    o.message = kv["message"];
    o.compared = kv["compared"] == "1";
    CompareResult& r = o.stats;
    r.width = int(num("width"));
    r.height = int(num("height"));
    r.meanError = num("mean");
    r.rmsError = num("rms");
    r.psnr = kv["psnr"] == "inf" ? INFINITY : num("psnr");
    r.maxError = int(num("max"));
    r.maxX = int(num("max_x"));
    r.maxY = int(num("max_y"));
    r.channels = long(num("channels"));
    r.over0 = long(num("over0"));
    r.over1 = long(num("over1"));
    r.over2 = long(num("over2"));
    r.sizeMismatch = kv["size_mismatch"] == "1";
    o.tolerance.limits.maxLevels = int(num("max_levels"));
    o.tolerance.limits.maxFractionOver1 = num("max_fraction_over_1");
    o.tolerance.limits.maxOffBy1 = long(num("max_off_by_1"));
    o.tolerance.reason = kv["reason"];
    o.tolerance.origin = kv["origin"];
    o.image = kv["image"];
    o.reference = kv["reference"];
    o.seconds = num("seconds");
    all.push_back(o);
  }
  std::sort(all.begin(), all.end(), [](const Outcome& a, const Outcome& b) { return a.name < b.name; });
  return all;
}

void judge(Outcome& o) {
  try {
    o.stats = compareFiles(o.image, o.reference);
  } catch (const Error& e) {
    o.passed = false;
    o.message = e.what();
    return;
  }
  o.compared = true;
  const CompareResult& r = o.stats;
  const CompareThresholds& t = o.tolerance.limits;
  o.passed = r.pass(t);
  if (r.sizeMismatch)
    o.message = fmt::format("the images differ in size: {} is {} x {}, the reference {} x {}", o.image, r.width,
                            r.height, r.otherWidth, r.otherHeight);
  else if (o.passed && r.over0 == 0) o.message = "identical";
  else
    o.message = fmt::format("{}: max {} levels (limit {}), {} of {} channels over 1 level (limit {:.4f}%), {} off by 1"
                            " (limit {})",
                            o.passed ? "within tolerance" : "over tolerance", r.maxError, t.maxLevels, r.over1,
                            r.channels, t.maxFractionOver1 * 100, r.over0 - r.over1,
                            t.maxOffBy1 < 0 ? "any" : std::to_string(t.maxOffBy1));
}

}  // namespace pvrt::golden
