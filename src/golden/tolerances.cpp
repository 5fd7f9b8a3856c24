#include "golden/tolerances.h"

#include "golden/tsv.h"

namespace pvrt::golden {

Tolerances readTolerances(const std::string& path) {
  const std::vector<std::string> lines = readLines(path, true);
  Tolerances t;
  for (size_t i = 1; i < lines.size(); ++i) {
    const int line = int(i) + 1;
    if (lines[i].empty()) continue;
    std::vector<std::string> f = splitTabs(lines[i]);
    if (f.size() == 3) f.emplace_back();  // no reason at all: said as such below
    if (f.size() != 4)
      throw tsvError(path, line, std::to_string(f.size()) + " fields; want scene, max_levels, max_fraction_over_1, reason");
    Tolerance x;
    x.limits.maxLevels = parseInt(f[1], path, line, "max_levels");
    x.limits.maxFractionOver1 = parseDouble(f[2], path, line, "max_fraction_over_1");
    x.reason = f[3];
    x.origin = printableName(path) + ":" + std::to_string(line);
    if (x.reason.find_first_not_of(" ") == std::string::npos)
      throw tsvError(path, line, f[0] + ": a tolerance needs its reason in the fourth field");
    if (f[0] == "*") t.suite = x;
    else if (!t.scenes.emplace(f[0], x).second) throw tsvError(path, line, "a second line for " + f[0]);
  }
  return t;
}

}  // namespace pvrt::golden
