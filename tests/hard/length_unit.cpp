// The scene's length unit (issue 29 item 2, issue 26 item 5): geometry is never lost to the
// tolerances, a copy of a scene at any scale is traced as the scene is, and a huge
// enclosing object changes nothing else. Each check renders two scenes in process that must
// give the same 8-bit image and prints the figures docs/robustness.md quotes:
//   length_unit sweep SCALE        paper1 scaled by SCALE against paper1
//   length_unit dome RADIUS        paper1 inside a black no_shadow sphere against paper1
//   length_unit speck RADIUS       a lit checkered plane with a sphere of RADIUS on it
//                                  against the plane alone
// Exit 0 when the figures are within the check's limit.
#include <cstdio>
#include <string>

#include <fmt/core.h>

#include "image/compare.h"
#include "image/image_io.h"
#include "render/renderer.h"
#include "render/scene.h"
#include "scene/xml_loader.h"
#include "sweep.h"

using namespace pvrt;

namespace {

constexpr int kWidth = 160, kHeight = 100;

RenderResult renderDesc(const SceneDesc& d, const Scene** keep = nullptr) {
  static Scene scene;  // kept for the caller's figures
  scene = buildScene(d);
  if (keep) *keep = &scene;
  RenderSettings rs;
  rs.width = kWidth;
  rs.height = kHeight;
  rs.backend = Backend::Serial;
  rs.threads = 1;
  rs.sampler.samplesPerPixel = 4;
  return render(scene, rs);
}

SceneDesc fromFile(const std::string& name) {
  return loadSceneFile(std::string(PVRT_SOURCE_DIR) + "/scenes/" + name);
}

SceneDesc fromString(const std::string& body) {
  return loadSceneString("<scene>\n" + body + "\n</scene>", "length_unit.xml");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: length_unit sweep|dome|speck VALUE\n");
    return 2;
  }
  const std::string what = argv[1];
  const double value = std::stod(argv[2]);
  SceneDesc a, b;
  if (what == "sweep") {
    b = fromFile("paper1.xml");
    a = hard::applySweep(b, {0, value});
  } else if (what == "dome") {
    // Black and unlit, the dome looks like the (black) background wherever it is seen, so
    // the two images must agree everywhere if nothing else changes.
    b = fromFile("paper1.xml");
    b.background = Color();
    a = b;
    SceneDesc dome = fromString(fmt::format(
        "<sphere center=\"0 0 0\" radius=\"{}\" no_shadow=\"true\"><pigment color=\"0\"/>"
        "<finish ambient=\"0\" diffuse=\"0\"/></sphere>", value));
    a.objects.push_back(dome.objects.front());  // its material is inline
  } else if (what == "speck") {
    const std::string plane =
        "<camera location=\"0 1 -3\" look_at=\"0 0 0\" right=\"1.6 0 0\"/>"
        "<light_source location=\"5 10 -5\"/>"
        "<plane normal=\"0 1 0\" distance=\"0\"><pigment><checker color1=\"0.85 0.85 0.85\" "
        "color2=\"0.25 0.3 0.4\"/></pigment></plane>";
    b = fromString(plane);
    a = fromString(plane + fmt::format("<sphere center=\"0 {0} 0\" radius=\"{0}\"><pigment color=\"1 0 0\"/>"
                                       "</sphere>", value));
  } else {
    std::fprintf(stderr, "length_unit: unknown check %s\n", what.c_str());
    return 2;
  }
  const Scene* scene = nullptr;
  const RenderResult ra = renderDesc(a, &scene);
  const double unit = scene->tol.unit, maxDistance = scene->tol.maxDistance;
  const RenderResult rb = renderDesc(b);
  const CompareResult c = compareImages8(encodeSrgb8(ra.image), encodeSrgb8(rb.image), kWidth, kHeight);
  const uint64_t nonFinite = ra.totals.nonFiniteSamples + rb.totals.nonFiniteSamples;
  // A speck may cover (part of) one pixel; everything else must match to a level.
  const long allowedOver1 = what == "speck" ? 3 : 0;
  const bool pass = c.over1 <= allowedOver1 && nonFinite == 0;
  fmt::print("LENGTH_UNIT {} {:g}: {} max_levels={} over1={} differ={} unit={:g} max_distance={:g} nonfinite={}\n",
             what, value, pass ? "PASS" : "FAIL", c.maxError, c.over1, c.over0, unit, maxDistance, nonFinite);
  return pass ? 0 : 1;
}
