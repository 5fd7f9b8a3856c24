#include "golden/suite.h"

#include <algorithm>
#include <filesystem>

#include <openssl/evp.h>

#include "core/error.h"
#include "pov_export.h"
#include "scene/xml_loader.h"

namespace pvrt::golden {

namespace fs = std::filesystem;

namespace {

// A tolerance line names a scene of the folder or of the manifest, or SCENE.VARIANT of one:
// a misspelt name would otherwise loosen nothing, unseen, and a removed scene's line linger.
bool namesASceneOf(const Suite& s, const std::string& name) {
  auto known = [&](const std::string& scene) {
    return std::binary_search(s.sceneNames.begin(), s.sceneNames.end(), scene) ||
           std::any_of(s.manifest.entries.begin(), s.manifest.entries.end(),
                       [&](const ManifestEntry& e) { return e.scene == scene; });
  };
  if (known(name)) return true;
  for (size_t dot = name.find('.'); dot != std::string::npos; dot = name.find('.', dot + 1))
    if (known(name.substr(0, dot))) return true;  // SCENE.VARIANT (a scene's name may hold dots)
  return false;
}

void checkToleranceNames(const Suite& s) {
  for (const auto& [name, t] : s.tolerances.scenes)
    if (!namesASceneOf(s, name))
      throw Error(ExitCode::SceneError, t.origin + ": error: " + printableName(name) + ": no scene " +
                                            printableName(s.scenePath(name)) +
                                            " and no reference of that name (a misspelt or removed scene?)");
}

}  // namespace

Suite openSuite(const std::string& scenes, const std::string& references) {
  std::error_code ec;
  if (!fs::is_directory(scenes, ec))
    throw Error(ExitCode::Usage, "pvrt golden: error: \"" + printableName(scenes) + "\" is not a folder of scenes");
  Suite s;
  s.scenes = scenes;
  s.references = references;
  for (const fs::directory_entry& f : fs::directory_iterator(scenes, ec))
    if (f.path().extension() == ".xml" && f.is_regular_file(ec)) s.sceneNames.push_back(f.path().stem().string());
  std::sort(s.sceneNames.begin(), s.sceneNames.end());
  s.manifest = readManifest(s.manifestPath());
  // A folder with neither scenes nor references has no test to run: passing it would let a
  // misspelt or emptied suite pass in CI (it did, with 0 tests), and make would write an empty
  // manifest into it.
  if (s.sceneNames.empty() && s.manifest.entries.empty())
    throw Error(ExitCode::Usage, "pvrt golden: error: \"" + printableName(scenes) +
                                     "\" holds no scenes (*.xml) and no references: nothing to test");
  s.tolerances = readTolerances(references + "/tolerances.tsv");
  checkToleranceNames(s);
  return s;
}

std::string exportSha256(const std::string& scenePath) { return sha256Hex(exportPov(loadSceneFile(scenePath)).sdl); }

std::string sha256Hex(const std::string& sdl) {
  unsigned char digest[EVP_MAX_MD_SIZE];
  unsigned int size = 0;
  if (!EVP_Digest(sdl.data(), sdl.size(), digest, &size, EVP_sha256(), nullptr))
    throw Error(ExitCode::Internal, "pvrt golden: internal error: SHA-256 failed");
  static const char* hex = "0123456789abcdef";
  std::string s;
  for (unsigned int i = 0; i < size; ++i) {
    s += hex[digest[i] >> 4];
    s += hex[digest[i] & 15];
  }
  return s;
}

namespace {

void check(const std::error_code& ec, const std::string& path) {
  if (ec) throw Error(ExitCode::OutputError, "cannot write \"" + printableName(path) + "\": " + ec.message());
}

}  // namespace

void makeFolder(const std::string& path) {
  std::error_code ec;
  fs::create_directories(path, ec);
  check(ec, path);
}

void copyFile(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::copy_file(from, to, fs::copy_options::overwrite_existing, ec);
  check(ec, to);
}

void renameFile(const std::string& from, const std::string& to) {
  std::error_code ec;
  fs::rename(from, to, ec);
  check(ec, to);
}

}  // namespace pvrt::golden
