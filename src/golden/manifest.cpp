#include "golden/manifest.h"

#include <algorithm>
#include <sstream>

#include <fmt/core.h>

#include "golden/tsv.h"

namespace pvrt::golden {

namespace {

const char* kHeader = "scene\tvariant\twidth\theight\taa_depth\tsdl_sha256\tpovray\tcommand";

bool before(const ManifestEntry& a, const ManifestEntry& b) {
  return a.scene != b.scene ? a.scene < b.scene : a.variant < b.variant;
}

}  // namespace

std::string ManifestEntry::imageName() const {
  std::istringstream words(command);
  for (std::string w, previous; words >> w; previous = w) {
    if (w.rfind("+O", 0) == 0) return w.substr(2);
    if (previous == "-o") return w;
  }
  return variant == "aa" ? scene + ".png" : scene + "." + variant + ".png";
}

const ManifestEntry* Manifest::find(const std::string& scene, const std::string& variant) const {
  for (const ManifestEntry& e : entries)
    if (e.scene == scene && e.variant == variant) return &e;
  return nullptr;
}

void Manifest::put(const ManifestEntry& e) {
  auto it = std::find_if(entries.begin(), entries.end(),
                         [&](const ManifestEntry& x) { return x.scene == e.scene && x.variant == e.variant; });
  if (it != entries.end()) *it = e;
  else entries.insert(std::upper_bound(entries.begin(), entries.end(), e, before), e);
}

Manifest readManifest(const std::string& path) {
  const std::vector<std::string> lines = readLines(path, true);
  Manifest m;
  for (size_t i = 1; i < lines.size(); ++i) {
    const int line = int(i) + 1;
    if (lines[i].empty()) continue;
    const std::vector<std::string> f = splitTabs(lines[i]);
    if (f.size() != 8) throw tsvError(path, line, fmt::format("{} fields where the header has 8", f.size()));
    ManifestEntry e;
    e.scene = f[0];
    e.variant = f[1];
    if (e.scene.empty() || e.variant.empty()) throw tsvError(path, line, "empty scene or variant");
    e.width = parseInt(f[2], path, line, "width");
    e.height = parseInt(f[3], path, line, "height");
    e.aaDepth = parseInt(f[4], path, line, "aa_depth");
    if (e.width == 0 || e.height == 0) throw tsvError(path, line, "width and height must be positive");
    e.sdlSha256 = f[5];
    e.renderer = f[6];
    e.command = f[7];
    e.line = line;
    if (m.find(e.scene, e.variant)) throw tsvError(path, line, "a second line for " + e.name());
    m.entries.push_back(e);
  }
  std::stable_sort(m.entries.begin(), m.entries.end(), before);
  return m;
}

std::string formatManifest(const Manifest& m) {
  std::string s = std::string(kHeader) + "\n";
  for (const ManifestEntry& e : m.entries)
    s += fmt::format("{}\t{}\t{}\t{}\t{}\t{}\t{}\t{}\n", e.scene, e.variant, e.width, e.height, e.aaDepth, e.sdlSha256,
                     e.renderer, e.command);
  return s;
}

}  // namespace pvrt::golden
