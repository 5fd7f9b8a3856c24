// reference/manifest.tsv: how each reference image was made, one tab-separated line each:
//   scene  variant  width  height  aa_depth  sdl_sha256  povray  command
// `povray` is the renderer's version (`3.7.0.10.unofficial`, or `pvrt 0.1.0` for a blessed
// pvrt output) and `command` the full command line that made the image; the image's name is
// the command's output (`+Oname.png` for POV-Ray, `-o name.png` for pvrt). The settings a
// golden test renders with are read from the command (render_settings.h), never assumed.
#pragma once

#include <string>
#include <vector>

namespace pvrt::golden {

struct ManifestEntry {
  std::string scene, variant;
  int width = 0, height = 0, aaDepth = 0;
  std::string sdlSha256, renderer, command;
  int line = 0;  // in the file, for messages (0: not read from a file)

  std::string name() const { return scene + "." + variant; }
  std::string imageName() const;  // the command's output file
  bool blessed() const { return command.rfind("pvrt ", 0) == 0; }
};

struct Manifest {
  std::vector<ManifestEntry> entries;  // sorted by scene, then variant

  const ManifestEntry* find(const std::string& scene, const std::string& variant) const;
  // Replaces the entry of the same scene and variant, or adds it, keeping the order.
  void put(const ManifestEntry& e);
};

// Throws pvrt::Error(SceneError) `manifest.tsv:LINE: error: what` for a malformed line.
Manifest readManifest(const std::string& path);
// The whole file, header first (written atomically by the caller).
std::string formatManifest(const Manifest& m);

}  // namespace pvrt::golden
