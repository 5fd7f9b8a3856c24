#include "pov_export.h"

#include <gtest/gtest.h>

#include "scene/xml_loader.h"

namespace pvrt {
namespace {

std::string exportXml(const std::string& xml) { return exportPov(loadSceneString(xml, "t.xml")).sdl; }

TEST(PovExport, MinimalSceneHasHeaderExplicitCameraAndNothingElse) {
  EXPECT_EQ(exportXml("<scene/>"),
            "// Exported by pvrt from t.xml\n"
            "#version 3.7;\n"
            "global_settings { assumed_gamma 1.0 max_trace_level 5 adc_bailout 0.00392156862745098 "
            "ambient_light rgb <1, 1, 1> }\n"
            "background { color rgb <0, 0, 0> }\n"
            "camera {\n  perspective\n  location <0, 0, 0>\n  direction <0, 0, 1>\n  up <0, 1, 0>\n"
            "  right <1.33, 0, 0>\n  sky <0, 1, 0>\n}\n");
}

TEST(PovExport, HeaderCarriesTheAntialiasingRecipeAndResolution) {
  const SceneDesc scene = loadSceneString(R"(<scene><image width="64" height="40"/></scene>)", "t.xml");
  const std::string sdl = exportPov(scene).sdl;
  const std::string file = withRecipe(sdl, scene, PovRecipe{3, "out/dir/t.pov"});
  EXPECT_EQ(file.rfind("// Exported by pvrt from t.xml\n// Render with: +W64 +H40\n"
                       "// Render as `pvrt render --sampler pov --spp 9` does: povray +It.pov +Ot.png +W64 +H40 -D +FN "
                       "+A0.0 +AM1 +R3 -J\n// (+A0.0 +AM1 +Rn -J",
                       0),
            0u)
      << file;
  EXPECT_EQ(file.substr(file.find("#version")), sdl.substr(sdl.find("#version")));  // the SDL untouched
  // Without <image>, pvrt's default resolution; without --aa-depth, -A.
  const SceneDesc bare = loadSceneString("<scene/>", "t.xml");
  EXPECT_NE(withRecipe(exportPov(bare).sdl, bare, {}).find("povray +Iscene.pov +Oscene.png +W320 +H240 -D +FN -A\n"),
            std::string::npos);
}

TEST(PovExport, SphereWithMaterialAndTransformsKeepsTextureBeforeTransforms) {
  const std::string sdl = exportXml(R"(<scene>
    <sphere center="1 2 3" radius="0.5">
      <pigment color="1 0.5 0.25" filter="0.1"/>
      <finish phong="0.8" reflection="0.3"/>
      <interior ior="1.5"/>
      <scale v="2"/><rotate v="0 90 0"/><translate v="1 0 0"/>
    </sphere></scene>)");
  const std::string want =
      "sphere { <1, 2, 3>, 0.5\n"
      "  texture {\n"
      "    pigment { color rgbft <1, 0.5, 0.25, 0.1, 0> }\n"
      "    finish {\n"
      "      ambient rgb <0.1, 0.1, 0.1> emission rgb <0, 0, 0>\n"
      "      diffuse 0.6 brilliance 1\n"
      "      phong 0.8 phong_size 40\n"
      "      specular 0 roughness 0.05\n"
      "      reflection { rgb <0.3, 0.3, 0.3>, rgb <0.3, 0.3, 0.3> falloff 1 exponent 1 }\n"
      "    }\n"
      "  }\n"
      "  interior { ior 1.5 }\n"
      "  scale <2, 2, 2>\n"
      "  rotate <0, 90, 0>\n"
      "  translate <1, 0, 0>\n"
      "}\n";
  EXPECT_NE(sdl.find(want), std::string::npos) << sdl;
}

TEST(PovExport, LightsWithEveryModifier) {
  const std::string sdl = exportXml(R"(<scene>
    <light_source location="0 8 0" color="1 0.9 0.8" fade_distance="2" fade_power="2" shadowless="true">
      <spotlight point_at="-2 0 1" radius="15" falloff="25" tightness="10"/>
      <area_light axis1="2 0 0" axis2="0 0 2" size1="3" size2="3"/>
    </light_source></scene>)");
  EXPECT_NE(sdl.find("light_source {\n  <0, 8, 0>\n  color rgb <1, 0.9, 0.8>\n"
                     "  spotlight point_at <-2, 0, 1> radius 15 falloff 25 tightness 10\n"
                     "  area_light <2, 0, 0>, <0, 0, 2>, 3, 3 adaptive 100\n"
                     "  fade_distance 2 fade_power 2\n  shadowless\n}\n"),
            std::string::npos)
      << sdl;
}

// POV-Ray's parser makes every oriented area light circular and warns ("Orient can only be
// used with circular area lights"); the export says `circular` itself, so POV-Ray reads it
// without a warning and to the same light.
TEST(PovExport, AnOrientedAreaLightIsWrittenCircular) {
  const std::string sdl = exportXml(R"(<scene>
    <light_source location="0 8 0">
      <area_light axis1="2 0 0" axis2="0 2 0" size1="3" size2="3" orient="true"/>
    </light_source></scene>)");
  EXPECT_NE(sdl.find("  area_light <2, 0, 0>, <0, 2, 0>, 3, 3 adaptive 100 circular orient\n"), std::string::npos) << sdl;
}

TEST(PovExport, NamedMaterialsAreDeclaredOnceAndReferenced) {
  const std::string sdl = exportXml(R"(<scene>
    <material name="glass"><pigment color="1 1 1" filter="0.9"/><interior ior="1.5"/></material>
    <sphere center="0 0 0" radius="1" material="glass"/>
    <box corner1="0 0 0" corner2="1 1 1" material="glass"/></scene>)");
  EXPECT_NE(sdl.find("#declare pvrt_glass = material {\n"), std::string::npos);
  EXPECT_NE(sdl.find("sphere { <0, 0, 0>, 1\n  material { pvrt_glass }\n}\n"), std::string::npos) << sdl;
  EXPECT_NE(sdl.find("box { <0, 0, 0>, <1, 1, 1>\n  material { pvrt_glass }\n}\n"), std::string::npos) << sdl;
}

TEST(PovExport, EveryShapeKeyword) {
  const std::string sdl = exportXml(R"(<scene>
    <plane normal="0 2 0" distance="1"/>
    <cylinder base="0 0 0" cap="0 1 0" radius="0.5" open="true"/>
    <cone base="0 0 0" base_radius="1" cap="0 1 0" cap_radius="0"/>
    <disc center="0 0 0" normal="0 1 0" radius="2" hole_radius="1"/>
    <triangle p1="0 0 0" p2="1 0 0" p3="0 1 0"/>
    <smooth_triangle p1="0 0 0" n1="0 0 1" p2="1 0 0" n2="0 0 1" p3="0 1 0" n3="0 0 1"/>
    <mesh><triangle p1="0 0 0" p2="1 0 0" p3="0 1 0"/></mesh></scene>)");
  for (const char* s : {"plane { <0, 2, 0>, 1\n", "cylinder { <0, 0, 0>, <0, 1, 0>, 0.5 open\n",
                        "cone { <0, 0, 0>, 1, <0, 1, 0>, 0\n", "disc { <0, 0, 0>, <0, 1, 0>, 2, 1\n",
                        "triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0>\n",
                        "smooth_triangle { <0, 0, 0>, <0, 0, 1>, <1, 0, 0>, <0, 0, 1>, <0, 1, 0>, <0, 0, 1>\n",
                        "mesh {\n  triangle { <0, 0, 0>, <1, 0, 0>, <0, 1, 0> }\n"})
    EXPECT_NE(sdl.find(s), std::string::npos) << s << "\n---\n" << sdl;
}

TEST(PovExport, NumbersReadBackExactly) {
  const std::string sdl = exportXml(R"(<scene><sphere center="0.1 0.2 0.30000000000000004" radius="1e-7"/></scene>)");
  EXPECT_NE(sdl.find("sphere { <0.1, 0.2, 0.30000000000000004>, 1e-07\n"), std::string::npos) << sdl;
}

TEST(PovExport, OutputIsByteStable) {
  const char* xml = R"(<scene><light_source location="1 2 3"/><sphere center="0 0 0" radius="1"/></scene>)";
  EXPECT_EQ(exportXml(xml), exportXml(xml));
}

TEST(PovExport, CommandLineFollowsTheRecipe) {
  EXPECT_EQ(povCommandLine("a.pov", "a.png", 320, 240, 3), "povray +Ia.pov +Oa.png +W320 +H240 -D +FN +A0.0 +AM1 +R3 -J");
  EXPECT_EQ(povCommandLine("a.pov", "a.png", 8, 6, 0), "povray +Ia.pov +Oa.png +W8 +H6 -D +FN -A");
}

TEST(PovExport, CommandLineCarriesTheAdaptiveAntialiasing) {
  EXPECT_EQ(povCommandLine("a.pov", "a.png", 160, 100, 3, {0.3, 1, 32}),
            "povray +Ia.pov +Oa.png +W160 +H100 -D +FN +A0.3 +AM1 +R3 -J");
  EXPECT_EQ(povCommandLine("a.pov", "a.png", 160, 100, 4, {0.1, 2, 16}),
            "povray +Ia.pov +Oa.png +W160 +H100 -D +FN +A0.1 +AM2 +R4 -J +BS16");
  // -A has no threshold to carry.
  EXPECT_EQ(povCommandLine("a.pov", "a.png", 8, 6, 0, {0.3, 2, 32}), "povray +Ia.pov +Oa.png +W8 +H6 -D +FN -A");
}

}  // namespace
}  // namespace pvrt
