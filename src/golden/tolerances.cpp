#include "golden/tolerances.h"

#include "golden/tsv.h"

namespace pvrt::golden {

Tolerances readTolerances(const std::string& path) {
  const std::vector<std::string> lines = readLines(path, true);
  Tolerances t;
  // With a max_off_by_1 column (named in the header), the reason is the fifth field.
  const bool offBy1 = !lines.empty() && splitTabs(lines[0]).size() > 3 && splitTabs(lines[0])[3] == "max_off_by_1";
  const size_t fields = offBy1 ? 5 : 4;
  const std::string want = offBy1 ? "scene, max_levels, max_fraction_over_1, max_off_by_1, reason"
                                  : "scene, max_levels, max_fraction_over_1, reason";
  // Without the header its line would be skipped as one, and that tolerance lost unseen.
  if (!lines.empty() && splitTabs(lines[0])[0] != "scene")
    throw tsvError(path, 1, "the first line must be the header \"scene<TAB>max_levels<TAB>max_fraction_over_1"
                            "[<TAB>max_off_by_1]<TAB>reason\", not a tolerance (" + splitTabs(lines[0])[0] + ")");
  for (size_t i = 1; i < lines.size(); ++i) {
    const int line = int(i) + 1;
    if (lines[i].empty()) continue;
    std::vector<std::string> f = splitTabs(lines[i]);
    if (f.size() == fields - 1) f.emplace_back();  // no reason at all: said as such below
    if (f.size() != fields) throw tsvError(path, line, std::to_string(f.size()) + " fields; want " + want);
    Tolerance x;
    x.limits.maxLevels = parseInt(f[1], path, line, "max_levels");
    x.limits.maxFractionOver1 = parseDouble(f[2], path, line, "max_fraction_over_1");
    if (offBy1) x.limits.maxOffBy1 = parseInt(f[3], path, line, "max_off_by_1");
    x.reason = f[fields - 1];
    x.origin = printableName(path) + ":" + std::to_string(line);
    if (x.reason.find_first_not_of(" ") == std::string::npos)
      throw tsvError(path, line, f[0] + ": a tolerance needs its reason in the last field");
    if (f[0] == "*") t.suite = x;
    else if (!t.scenes.emplace(f[0], x).second) throw tsvError(path, line, "a second line for " + f[0]);
  }
  return t;
}

}  // namespace pvrt::golden
