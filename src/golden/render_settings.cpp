#include "golden/render_settings.h"

#include <cctype>
#include <cstdlib>
#include <sstream>

#include "golden/tsv.h"

namespace pvrt::golden {

namespace {

std::vector<std::string> words(const std::string& s) {
  std::istringstream in(s);
  std::vector<std::string> w;
  for (std::string x; in >> x;) w.push_back(x);
  return w;
}

// POV-Ray's switches are case-insensitive and take their value glued on: +AM1, +r3, +A0.0.
bool isSwitch(const std::string& w, const std::string& name) {
  if (w.size() < name.size() + 1 || (w[0] != '+' && w[0] != '-')) return false;
  for (size_t i = 0; i < name.size(); ++i)
    if (std::toupper(static_cast<unsigned char>(w[i + 1])) != name[i]) return false;
  return true;
}

}  // namespace

std::vector<std::string> renderSettings(const ManifestEntry& e, const std::string& manifestPath) {
  const std::vector<std::string> w = words(e.command);
  if (e.blessed()) {  // pvrt render SCENE.xml -o NAME.png SETTINGS...
    std::vector<std::string> settings;
    for (size_t i = 3; i < w.size(); ++i) {
      // The output and size come from the manifest's columns, not from the command.
      if (w[i] == "-o" || w[i] == "-W" || w[i] == "-H" || w[i] == "--width" || w[i] == "--height") {
        ++i;
        continue;
      }
      settings.push_back(w[i]);
    }
    return settings;
  }
  bool antialias = false, jitter = true;
  int method = 1, depth = 3, block = 32;
  double threshold = 0.3;  // POV-Ray's defaults
  std::string thresholdText = "0.3";
  for (const std::string& x : w) {
    const bool on = x[0] == '+';
    if (isSwitch(x, "AM")) method = std::atoi(x.c_str() + 3);
    else if (isSwitch(x, "A")) {
      antialias = on;
      if (on && x.size() > 2) {
        thresholdText = x.substr(2);
        threshold = std::atof(thresholdText.c_str());
      }
    } else if (isSwitch(x, "R")) depth = std::atoi(x.c_str() + 2);
    else if (isSwitch(x, "J")) jitter = on && !(x.size() > 2 && std::atof(x.c_str() + 2) == 0);
    else if (isSwitch(x, "BS")) block = std::atoi(x.c_str() + 3);
  }
  if (!antialias) return {"--sampler", "pov", "--spp", "1"};
  const bool known = !jitter && (method == 1 || method == 2) && depth >= 1 && depth <= 9 && block >= 1;
  if (known && method == 1 && threshold == 0.0 && block == 32)
    return {"--sampler", "pov", "--spp", std::to_string(depth * depth)};
  // POV-Ray's adaptive antialiasing: pvrt's --aa-threshold, --aa-method and --aa-block.
  if (known)
    return {"--sampler",     "pov",         "--spp",      std::to_string(depth * depth), "--aa-threshold",
            thresholdText,   "--aa-method", std::to_string(method), "--aa-block", std::to_string(block)};
  throw tsvError(manifestPath, e.line,
                 e.name() + ": pvrt golden has no pvrt settings for POV-Ray's \"" + povrayAntialiasing(e.command) +
                     "\" (only +An +AM1/+AM2 +Rn [+BSn] -J and -A; golden/render_settings.cpp maps them)");
}

std::string povrayAntialiasing(const std::string& command) {
  const size_t at = command.find("+FN");
  if (at == std::string::npos) return "";
  const size_t start = command.find_first_not_of(' ', at + 3);
  return start == std::string::npos ? "" : command.substr(start);
}

int aaDepthOf(const std::string& antialiasing) {
  int depth = 0;
  bool antialias = false;
  for (const std::string& x : words(antialiasing)) {
    if (isSwitch(x, "AM")) continue;
    if (isSwitch(x, "A")) antialias = x[0] == '+';
    else if (isSwitch(x, "R")) depth = std::atoi(x.c_str() + 2);
  }
  return antialias ? (depth > 0 ? depth : 3) : 0;
}

}  // namespace pvrt::golden
