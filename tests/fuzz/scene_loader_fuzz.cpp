// libFuzzer target for the scene loader: the bytes are a scene file; it is loaded from
// memory and built (the stage after loading: camera, lights, materials, BVH). Anything but
// success or a pvrt::Error(SceneError) with a one-line `fuzz.xml:LINE: error: ` message is a
// finding: a crash, a sanitizer report, another exception, or a malformed message. So is a
// difference between loading the bytes whole and in pieces of a byte (scene/xml_split.h):
// the same scene, or the same message; and a difference between the cut found by one scan
// and by scans of parts of a few bytes joined (splitXmlRoot's partBytes).
// Built with -DPVRT_FUZZ=ON by tools/fuzz.sh (clang only).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <string_view>

#include "core/error.h"
#include "render/scene.h"
#include "scene/xml_loader.h"
#include "scene/xml_split.h"
#include "scene/xml_writer.h"

namespace {

// The scene as XML, or the error's message.
std::string outcome(const std::string& text, const std::string& name, size_t pieceBytes) {
  try {
    return pvrt::sceneToXml(pvrt::loadSceneString(text, name, {pieceBytes}));
  } catch (const pvrt::Error& e) {
    return std::string("error: ") + e.what();
  }
}

// The cut, as text.
std::string cut(const std::string& text, size_t partBytes) {
  const std::optional<pvrt::XmlSplit> split = pvrt::splitXmlRoot(
      text, 1, [](std::string_view name) { return name.size() % 2 == 0; }, partBytes);
  if (!split) return "none";
  std::string out = std::to_string(split->bodyBegin) + " " + std::to_string(split->bodyEnd) + " " +
                    std::to_string(split->elements) + " " + std::to_string(split->bodyLines);
  for (const pvrt::XmlPiece& p : split->pieces)
    out += " " + std::to_string(p.begin) + "-" + std::to_string(p.end) + ":" + std::to_string(p.firstLine) + ":" +
           std::to_string(p.counted);
  return out;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string name = "fuzz.xml";
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string whole = outcome(text, name, std::numeric_limits<size_t>::max());
  if (const std::string pieces = outcome(text, name, 1); pieces != whole) {
    std::fprintf(stderr, "loaded whole:\n%s\nloaded in pieces:\n%s\n", whole.c_str(), pieces.c_str());
    std::abort();
  }
  if (const std::string one = cut(text, std::numeric_limits<size_t>::max()), parts = cut(text, 3); parts != one) {
    std::fprintf(stderr, "cut by one scan:\n%s\ncut by scans of parts:\n%s\n", one.c_str(), parts.c_str());
    std::abort();
  }
  try {
    const pvrt::Scene scene = pvrt::buildScene(pvrt::loadSceneString(text, name));
  } catch (const pvrt::Error& e) {
    const std::string m = e.what();
    const size_t colon = m.find(':', name.size() + 1);
    const bool located = m.compare(0, name.size() + 1, name + ":") == 0 && colon != std::string::npos &&
                         colon > name.size() + 1 &&
                         m.find_first_not_of("0123456789", name.size() + 1) == colon &&
                         m.compare(colon, 9, ": error: ") == 0;
    if (e.code() != pvrt::ExitCode::SceneError || !located || m.find('\n') != std::string::npos) {
      std::fprintf(stderr, "bad error (exit code %d): %s\n", int(e.code()), m.c_str());
      std::abort();
    }
  }
  return 0;
}
