// A golden suite: a folder of XML scenes and a folder of references beside them.
//
//   SCENES/*.xml                     the scenes (any folder; the repository's is scenes/)
//   REFERENCES/manifest.tsv          one line per reference: how it was made (manifest.h)
//   REFERENCES/tolerances.tsv        optional: looser thresholds, each with its reason
//   REFERENCES/<scene>[.variant].png the reference images
//
// Everything `pvrt golden` does starts from openSuite(); nothing is hard-coded about the
// repository's own scenes.
#pragma once

#include <string>
#include <vector>

#include "golden/manifest.h"
#include "golden/tolerances.h"

namespace pvrt::golden {

struct Suite {
  std::string scenes;      // folder of *.xml
  std::string references;  // folder of manifest.tsv, tolerances.tsv and the images
  std::vector<std::string> sceneNames;  // the scenes' file names without .xml, sorted
  Manifest manifest;
  Tolerances tolerances;

  std::string scenePath(const std::string& scene) const { return scenes + "/" + scene + ".xml"; }
  std::string manifestPath() const { return references + "/manifest.tsv"; }
  std::string referencePath(const ManifestEntry& e) const { return references + "/" + e.imageName(); }
};

// Reads the folder listing, the manifest (empty when absent) and the tolerances.
// Throws pvrt::Error: Usage when a folder is missing, SceneError (`file:line: error: ...`)
// for a malformed manifest or tolerance line.
Suite openSuite(const std::string& scenes, const std::string& references);

// SHA-256 of the scene's POV-Ray export: what the manifest records, so that a reference made
// from an older version of the scene (or of the exporter) is known to be stale.
std::string exportSha256(const std::string& scenePath);
std::string sha256Hex(const std::string& bytes);

// The file-system steps of a run, each throwing pvrt::Error(OutputError) `cannot write "PATH": why`
// instead of a std::filesystem exception.
void makeFolder(const std::string& path);
void copyFile(const std::string& from, const std::string& to);
void renameFile(const std::string& from, const std::string& to);

}  // namespace pvrt::golden
