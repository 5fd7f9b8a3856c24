// The XML loader: every element and attribute lands in the right SceneDesc field (with
// POV-Ray's defaults when left out), and every kind of bad input is refused with the exact
// `name:line: element: what` message and ExitCode::SceneError.
#include "scene/xml_loader.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "core/error.h"
#include "parallel/threads.h"
#include "scene/xml_writer.h"

namespace pvrt {
namespace {

SceneDesc load(const std::string& xml) { return loadSceneString(xml, "t.xml"); }

// Loads `xml` as "t.xml" and checks that it is refused with exactly `want`.
void expectSceneError(const std::string& xml, const std::string& want) {
  try {
    loadSceneString(xml, "t.xml");
    ADD_FAILURE() << "loaded without error; expected: " << want;
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), want);
    EXPECT_EQ(e.code(), ExitCode::SceneError) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << "threw something other than pvrt::Error: " << e.what();
  }
}

#define EXPECT_SCENE_ERROR(xml, want)  \
  do {                                 \
    SCOPED_TRACE(xml);                 \
    expectSceneError((xml), (want));   \
  } while (0)

// One element inside <scene>, on line 2.
std::string inScene(const std::string& body) { return "<scene>\n" + body + "\n</scene>"; }

void expectVec(const Vec3& v, double x, double y, double z) {
  EXPECT_EQ(v.x, x);
  EXPECT_EQ(v.y, y);
  EXPECT_EQ(v.z, z);
}
void expectColor(const Color& c, double r, double g, double b) {
  EXPECT_EQ(c.r, r);
  EXPECT_EQ(c.g, g);
  EXPECT_EQ(c.b, b);
}
void expectNear(const Vec3& v, double x, double y, double z) {
  EXPECT_NEAR(v.x, x, 1e-12);
  EXPECT_NEAR(v.y, y, 1e-12);
  EXPECT_NEAR(v.z, z, 1e-12);
}

// ---------------------------------------------------------------- scene-level elements

TEST(XmlLoader, EmptySceneHasPovRayDefaults) {
  const SceneDesc s = load("<scene/>");
  EXPECT_EQ(s.path, "t.xml");
  expectVec(s.camera.location, 0, 0, 0);
  expectVec(s.camera.direction, 0, 0, 1);
  expectVec(s.camera.up, 0, 1, 0);
  expectVec(s.camera.right, 1.33, 0, 0);
  expectVec(s.camera.sky, 0, 1, 0);
  EXPECT_FALSE(s.camera.lookAt);
  EXPECT_FALSE(s.camera.angle);
  EXPECT_TRUE(s.camera.transforms.empty());
  EXPECT_EQ(s.globals.maxTraceLevel, 5);
  EXPECT_EQ(s.globals.adcBailout, 1.0 / 255.0);
  expectColor(s.globals.ambientLight, 1, 1, 1);
  expectColor(s.background, 0, 0, 0);
  EXPECT_FALSE(s.image);
  EXPECT_TRUE(s.lights.empty());
  EXPECT_TRUE(s.materials.empty());
  EXPECT_TRUE(s.objects.empty());
}

TEST(XmlLoader, DefaultNameIsString) {
  try {
    loadSceneString("<scene><sphere/></scene>");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "<string>:1: error: sphere: missing required attribute 'center'");
  }
}

TEST(XmlLoader, DeclarationCommentsAndWhitespaceAreIgnored) {
  const SceneDesc s = load(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<!-- a comment -->\n<scene>\n  <!-- inside -->\n"
      "  <sphere center=\"0 0 0\" radius=\"1\"><!-- in an object --></sphere>\n</scene>\n<!-- after -->\n");
  ASSERT_EQ(s.objects.size(), 1u);
  EXPECT_EQ(s.objects[0].loc.line, 5);
}

TEST(XmlLoader, ImageGlobalsAndBackground) {
  const SceneDesc s = load(inScene(
      "<image width=\"640\" height=\"480\"/>\n"
      "<global_settings max_trace_level=\"12\" adc_bailout=\"0.01\" ambient_light=\"0.5 0.25 0.125\"/>\n"
      "<background color=\"0.1 0.2 0.3\"/>"));
  ASSERT_TRUE(s.image);
  EXPECT_EQ(s.image->width, 640);
  EXPECT_EQ(s.image->height, 480);
  EXPECT_EQ(s.image->loc.line, 2);
  EXPECT_EQ(s.globals.maxTraceLevel, 12);
  EXPECT_EQ(s.globals.adcBailout, 0.01);
  expectColor(s.globals.ambientLight, 0.5, 0.25, 0.125);
  EXPECT_EQ(s.globals.loc.line, 3);
  expectColor(s.background, 0.1, 0.2, 0.3);
}

TEST(XmlLoader, GlobalSettingsAndBackgroundDefaults) {
  const SceneDesc s = load(inScene("<global_settings/><background/>"));
  EXPECT_EQ(s.globals.maxTraceLevel, 5);
  EXPECT_EQ(s.globals.adcBailout, 1.0 / 255.0);
  expectColor(s.globals.ambientLight, 1, 1, 1);
  expectColor(s.background, 0, 0, 0);
  EXPECT_EQ(load(inScene("<global_settings max_trace_level=\"256\" adc_bailout=\"0\"/>")).globals.maxTraceLevel,
            256);
}

TEST(XmlLoader, CameraWithEveryAttributeAndTransforms) {
  const SceneDesc s = load(inScene(
      "<camera location=\"1 2 3\" direction=\"0 0 2\" up=\"0 2 0\" right=\"-1.6 0 0\" sky=\"0 0 1\"\n"
      "        look_at=\"4 5 6\" angle=\"45\">\n"
      "  <rotate v=\"0 30 0\"/>\n"
      "  <translate v=\"0 1 0\"/>\n"
      "</camera>"));
  const CameraDesc& c = s.camera;
  expectVec(c.location, 1, 2, 3);
  expectVec(c.direction, 0, 0, 2);
  expectVec(c.up, 0, 2, 0);
  expectVec(c.right, -1.6, 0, 0);
  expectVec(c.sky, 0, 0, 1);
  ASSERT_TRUE(c.lookAt);
  expectVec(*c.lookAt, 4, 5, 6);
  ASSERT_TRUE(c.angle);
  EXPECT_EQ(*c.angle, 45);
  ASSERT_EQ(c.transforms.steps.size(), 2u);
  EXPECT_EQ(c.transforms.steps[0].kind, TransformStep::Kind::Rotate);
  expectVec(c.transforms.steps[0].v, 0, 30, 0);
  EXPECT_EQ(c.transforms.steps[0].loc.line, 4);
  EXPECT_EQ(c.transforms.steps[1].kind, TransformStep::Kind::Translate);
  EXPECT_EQ(c.transforms.steps[1].loc.line, 5);
  EXPECT_EQ(c.loc.line, 2);
  EXPECT_EQ(c.loc.file.str(), "t.xml");
}

TEST(XmlLoader, LightSourceDefaults) {
  const SceneDesc s = load(inScene("<light_source location=\"1 2 3\"/>"));
  ASSERT_EQ(s.lights.size(), 1u);
  const LightDesc& l = s.lights[0];
  expectVec(l.location, 1, 2, 3);
  expectColor(l.color, 1, 1, 1);
  EXPECT_EQ(l.fadeDistance, 0);
  EXPECT_EQ(l.fadePower, 0);
  EXPECT_FALSE(l.shadowless);
  EXPECT_FALSE(l.spot);
  EXPECT_FALSE(l.area);
  EXPECT_EQ(l.loc.line, 2);
}

TEST(XmlLoader, LightSourceWithEveryAttributeSpotlightAndAreaLight) {
  const SceneDesc s = load(inScene(
      "<light_source location=\"0 8 0\" color=\"0.5\" fade_distance=\"2\" fade_power=\"1.5\" shadowless=\"true\">\n"
      "  <spotlight point_at=\"1 0 1\" radius=\"10\" falloff=\"20\" tightness=\"5\"/>\n"
      "  <area_light axis1=\"2 0 0\" axis2=\"0 0 3\" size1=\"4\" size2=\"5\" adaptive=\"1\" circular=\"true\" "
      "orient=\"true\"/>\n"
      "</light_source>\n"
      "<light_source location=\"0 0 0\" shadowless=\"false\"/>"));
  ASSERT_EQ(s.lights.size(), 2u);
  const LightDesc& l = s.lights[0];
  expectColor(l.color, 0.5, 0.5, 0.5);
  EXPECT_EQ(l.fadeDistance, 2);
  EXPECT_EQ(l.fadePower, 1.5);
  EXPECT_TRUE(l.shadowless);
  ASSERT_TRUE(l.spot);
  expectVec(l.spot->pointAt, 1, 0, 1);
  EXPECT_EQ(l.spot->radius, 10);
  EXPECT_EQ(l.spot->falloff, 20);
  EXPECT_EQ(l.spot->tightness, 5);
  ASSERT_TRUE(l.area);
  expectVec(l.area->axis1, 2, 0, 0);
  expectVec(l.area->axis2, 0, 0, 3);
  EXPECT_EQ(l.area->size1, 4);
  EXPECT_EQ(l.area->size2, 5);
  EXPECT_EQ(l.area->adaptive, 1);
  EXPECT_TRUE(l.area->circular);
  EXPECT_TRUE(l.area->orient);
  EXPECT_FALSE(s.lights[1].shadowless);
  EXPECT_EQ(s.lights[1].loc.line, 6);
}

TEST(XmlLoader, SpotlightAndAreaLightDefaults) {
  const SceneDesc s = load(inScene(
      "<light_source location=\"0 5 0\"><spotlight/><area_light axis1=\"1 0 0\" axis2=\"0 1 0\"/></light_source>"));
  const LightDesc& l = s.lights.at(0);
  ASSERT_TRUE(l.spot);
  expectVec(l.spot->pointAt, 0, 0, 1);
  EXPECT_EQ(l.spot->radius, 30);
  EXPECT_EQ(l.spot->falloff, 45);
  EXPECT_EQ(l.spot->tightness, 0);
  ASSERT_TRUE(l.area);
  EXPECT_EQ(l.area->size1, 1);
  EXPECT_EQ(l.area->size2, 1);
  EXPECT_EQ(l.area->adaptive, 100);
  EXPECT_FALSE(l.area->circular);
  EXPECT_FALSE(l.area->orient);
}

// ---------------------------------------------------------------- materials

TEST(XmlLoader, NamedMaterialWithEveryAttribute) {
  const SceneDesc s = load(inScene(
      "<material name=\"Glass_2\">\n"
      "  <pigment color=\"1 0.5 0.25\" filter=\"0.75\" transmit=\"0.125\"/>\n"
      "  <finish ambient=\"0.2 0.3 0.4\" emission=\"0.5\" diffuse=\"0.9\" brilliance=\"2\" phong=\"0.8\"\n"
      "          phong_size=\"90\" specular=\"0.3\" roughness=\"0.01\" metallic=\"0.5\" conserve_energy=\"true\"\n"
      "          reflection=\"0.1 0.2 0.3\"/>\n"
      "  <interior ior=\"1.5\" fade_distance=\"3\" fade_power=\"2\" fade_color=\"0.5 0.6 0.7\"/>\n"
      "</material>"));
  ASSERT_EQ(s.materials.size(), 1u);
  const MaterialDesc& m = s.materials[0];
  EXPECT_EQ(m.name, "Glass_2");
  EXPECT_EQ(m.loc.line, 2);
  expectColor(m.pigment.color.rgb, 1, 0.5, 0.25);
  EXPECT_EQ(m.pigment.color.filter, 0.75);
  EXPECT_EQ(m.pigment.color.transmit, 0.125);
  EXPECT_FALSE(m.pigment.checker);
  EXPECT_EQ(m.pigment.loc.line, 3);
  const FinishDesc& f = *m.finish;
  expectColor(f.ambient, 0.2, 0.3, 0.4);
  expectColor(f.emission, 0.5, 0.5, 0.5);
  EXPECT_EQ(f.diffuse, 0.9);
  EXPECT_EQ(f.brilliance, 2);
  EXPECT_EQ(f.phong, 0.8);
  EXPECT_EQ(f.phongSize, 90);
  EXPECT_EQ(f.specular, 0.3);
  EXPECT_EQ(f.roughness, 0.01);
  EXPECT_EQ(f.metallic, 0.5);
  EXPECT_TRUE(f.conserveEnergy);
  expectColor(f.reflection.min, 0.1, 0.2, 0.3);
  expectColor(f.reflection.max, 0.1, 0.2, 0.3);
  EXPECT_EQ(f.reflection.falloff, 1);
  EXPECT_FALSE(f.reflection.fresnel);
  const InteriorDesc& in = *m.interior;
  EXPECT_EQ(in.ior, 1.5);
  EXPECT_EQ(in.fadeDistance, 3);
  EXPECT_EQ(in.fadePower, 2);
  expectColor(in.fadeColor, 0.5, 0.6, 0.7);
}

TEST(XmlLoader, EmptyMaterialPartsHaveDefaults) {
  const SceneDesc s = load(inScene("<material name=\"m\"><pigment/><finish/><interior/></material>"));
  const MaterialDesc& m = s.materials.at(0);
  expectColor(m.pigment.color.rgb, 0, 0, 0);
  EXPECT_EQ(m.pigment.color.filter, 0);
  EXPECT_EQ(m.pigment.color.transmit, 0);
  EXPECT_TRUE(m.pigment.transforms.empty());
  const FinishDesc& f = *m.finish;
  expectColor(f.ambient, 0.1, 0.1, 0.1);
  expectColor(f.emission, 0, 0, 0);
  EXPECT_EQ(f.diffuse, 0.6);
  EXPECT_EQ(f.brilliance, 1);
  EXPECT_EQ(f.phong, 0);
  EXPECT_EQ(f.phongSize, 40);
  EXPECT_EQ(f.specular, 0);
  EXPECT_EQ(f.roughness, 0.05);
  EXPECT_EQ(f.metallic, 0);
  EXPECT_FALSE(f.conserveEnergy);
  EXPECT_TRUE(f.reflection.isZero());
  EXPECT_EQ(f.reflection.falloff, 1);
  EXPECT_EQ(f.reflection.exponent, 1);
  EXPECT_EQ(f.reflection.metallic, 0);
  EXPECT_FALSE(f.reflection.fresnel);
  EXPECT_EQ(m.interior->ior, 1);
  EXPECT_EQ(m.interior->fadeDistance, 0);
  EXPECT_EQ(m.interior->fadePower, 0);
  expectColor(m.interior->fadeColor, 0, 0, 0);
}

TEST(XmlLoader, MaterialWithoutChildrenIsAllDefaults) {
  const SceneDesc s = load(inScene("<material name=\"plain\"/>"));
  ASSERT_EQ(s.materials.size(), 1u);
  EXPECT_EQ(s.materials[0].finish->diffuse, 0.6);
  EXPECT_EQ(s.materials[0].interior->ior, 1);
}

TEST(XmlLoader, CheckerPigmentWithTransforms) {
  const SceneDesc s = load(inScene(
      "<material name=\"floor\">\n"
      "  <pigment>\n"
      "    <checker color1=\"1 1 1\" filter1=\"0.1\" transmit1=\"0.2\" color2=\"0.5\" filter2=\"0.3\" "
      "transmit2=\"0.4\"/>\n"
      "    <scale v=\"2\"/>\n"
      "    <rotate v=\"0 45 0\"/>\n"
      "  </pigment>\n"
      "</material>"));
  const PigmentDesc& p = s.materials.at(0).pigment;
  ASSERT_TRUE(p.checker);
  expectColor(p.checker->color1.rgb, 1, 1, 1);
  EXPECT_EQ(p.checker->color1.filter, 0.1);
  EXPECT_EQ(p.checker->color1.transmit, 0.2);
  expectColor(p.checker->color2.rgb, 0.5, 0.5, 0.5);
  EXPECT_EQ(p.checker->color2.filter, 0.3);
  EXPECT_EQ(p.checker->color2.transmit, 0.4);
  ASSERT_EQ(p.transforms.steps.size(), 2u);
  EXPECT_EQ(p.transforms.steps[0].kind, TransformStep::Kind::Scale);
  expectVec(p.transforms.steps[0].v, 2, 2, 2);
  EXPECT_EQ(p.transforms.steps[1].kind, TransformStep::Kind::Rotate);
  EXPECT_EQ(p.transforms.steps[1].loc.line, 6);
  EXPECT_TRUE(p.hasTransparency());
}

TEST(XmlLoader, CheckerDefaultsAreBlueAndGreen) {
  const SceneDesc s = load(inScene("<plane><pigment><checker/></pigment></plane>"));
  const PigmentDesc& p = s.objects.at(0).material.pigment;
  ASSERT_TRUE(p.checker);
  expectColor(p.checker->color1.rgb, 0, 0, 1);
  expectColor(p.checker->color2.rgb, 0, 1, 0);
  EXPECT_EQ(p.checker->color1.filter, 0);
  EXPECT_EQ(p.checker->color2.transmit, 0);
  EXPECT_FALSE(p.hasTransparency());
}

TEST(XmlLoader, PlainPigmentMayCarryTransforms) {
  const SceneDesc s = load(inScene("<sphere center=\"0 0 0\" radius=\"1\"><pigment color=\"1 0 0\">"
                                   "<translate v=\"1 2 3\"/></pigment></sphere>"));
  const PigmentDesc& p = s.objects.at(0).material.pigment;
  EXPECT_FALSE(p.checker);
  ASSERT_EQ(p.transforms.steps.size(), 1u);
  expectVec(p.transforms.steps[0].v, 1, 2, 3);
}

TEST(XmlLoader, ReflectionElementWithEveryAttribute) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"0 0 0\" radius=\"1\"><finish>"
      "<reflection min=\"0.1\" max=\"0.9 0.8 0.7\" falloff=\"2\" fresnel=\"true\" exponent=\"0.5\" metallic=\"0.25\"/>"
      "</finish></sphere>"));
  const ReflectionDesc& r = s.objects.at(0).material.finish->reflection;
  expectColor(r.min, 0.1, 0.1, 0.1);
  expectColor(r.max, 0.9, 0.8, 0.7);
  EXPECT_EQ(r.falloff, 2);
  EXPECT_TRUE(r.fresnel);
  EXPECT_EQ(r.exponent, 0.5);
  EXPECT_EQ(r.metallic, 0.25);
}

TEST(XmlLoader, ReflectionElementMaxDefaultsToMin) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"0 0 0\" radius=\"1\"><finish><reflection min=\"0.3 0.2 0.1\"/></finish></sphere>"));
  const ReflectionDesc& r = s.objects.at(0).material.finish->reflection;
  expectColor(r.min, 0.3, 0.2, 0.1);
  expectColor(r.max, 0.3, 0.2, 0.1);
  EXPECT_EQ(r.falloff, 1);
  EXPECT_EQ(r.exponent, 1);
  EXPECT_FALSE(r.fresnel);

  const SceneDesc t = load(inScene(
      "<sphere center=\"0 0 0\" radius=\"1\"><finish><reflection max=\"0.5\"/></finish></sphere>"));
  const ReflectionDesc& q = t.objects.at(0).material.finish->reflection;
  expectColor(q.min, 0, 0, 0);
  expectColor(q.max, 0.5, 0.5, 0.5);
}

// ---------------------------------------------------------------- objects

TEST(XmlLoader, SphereWithInlineMaterialAndNoShadow) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"1 2 3\" radius=\"0.5\" no_shadow=\"true\">\n"
      "  <pigment color=\"1 0 0\"/>\n"
      "  <finish phong=\"1\"/>\n"
      "  <interior ior=\"1.33\"/>\n"
      "</sphere>"));
  ASSERT_EQ(s.objects.size(), 1u);
  const ObjectDesc& o = s.objects[0];
  const auto* sp = std::get_if<SphereDesc>(&o.shape);
  ASSERT_NE(sp, nullptr);
  expectVec(sp->center, 1, 2, 3);
  EXPECT_EQ(sp->radius, 0.5);
  EXPECT_TRUE(o.noShadow);
  EXPECT_EQ(o.namedMaterial, -1);
  EXPECT_EQ(o.material.name, "");
  expectColor(o.material.pigment.color.rgb, 1, 0, 0);
  EXPECT_EQ(o.material.finish->phong, 1);
  EXPECT_EQ(o.material.finish->diffuse, 0.6);
  EXPECT_EQ(o.material.interior->ior, 1.33);
  EXPECT_EQ(o.loc.line, 2);
  EXPECT_EQ(o.material.pigment.loc.line, 3);
  EXPECT_STREQ(shapeName(o.shape), "sphere");
}

TEST(XmlLoader, ObjectWithoutMaterialHasDefaultMaterial) {
  const SceneDesc s = load(inScene("<sphere center=\"0 0 0\" radius=\"1\"/>"));
  const ObjectDesc& o = s.objects.at(0);
  EXPECT_EQ(o.namedMaterial, -1);
  EXPECT_FALSE(o.noShadow);
  expectColor(o.material.pigment.color.rgb, 0, 0, 0);
  EXPECT_EQ(o.material.finish->diffuse, 0.6);
  EXPECT_EQ(o.material.interior->ior, 1);
  EXPECT_TRUE(o.transforms.empty());
}

TEST(XmlLoader, PlaneWithAndWithoutAttributes) {
  const SceneDesc s = load(inScene("<plane/>\n<plane normal=\"1 1 0\" distance=\"-2.5\"/>"));
  ASSERT_EQ(s.objects.size(), 2u);
  const auto& a = std::get<PlaneDesc>(s.objects[0].shape);
  expectVec(a.normal, 0, 1, 0);
  EXPECT_EQ(a.distance, 0);
  const auto& b = std::get<PlaneDesc>(s.objects[1].shape);
  expectVec(b.normal, 1, 1, 0);  // kept as written: not normalised
  EXPECT_EQ(b.distance, -2.5);
  EXPECT_EQ(s.objects[1].loc.line, 3);
}

TEST(XmlLoader, Box) {
  const SceneDesc s = load(inScene("<box corner1=\"-1 -2 -3\" corner2=\"1 2 3\"/>"));
  const auto& b = std::get<BoxDesc>(s.objects.at(0).shape);
  expectVec(b.corner1, -1, -2, -3);
  expectVec(b.corner2, 1, 2, 3);
  EXPECT_STREQ(shapeName(s.objects[0].shape), "box");
}

TEST(XmlLoader, Cylinder) {
  const SceneDesc s = load(inScene("<cylinder base=\"0 0 0\" cap=\"0 2 0\" radius=\"0.5\"/>\n"
                                   "<cylinder base=\"0 0 0\" cap=\"1 0 0\" radius=\"1\" open=\"true\"/>"));
  const auto& a = std::get<CylinderDesc>(s.objects.at(0).shape);
  expectVec(a.base, 0, 0, 0);
  expectVec(a.cap, 0, 2, 0);
  EXPECT_EQ(a.radius, 0.5);
  EXPECT_FALSE(a.open);
  EXPECT_TRUE(std::get<CylinderDesc>(s.objects.at(1).shape).open);
}

TEST(XmlLoader, ConeWithDefaultsAndValues) {
  const SceneDesc s = load(inScene(
      "<cone base=\"0 0 0\" cap=\"0 1 0\"/>\n"
      "<cone base=\"0 0 0\" base_radius=\"0\" cap=\"0 1 0\" cap_radius=\"0.5\" open=\"true\"/>"));
  const auto& a = std::get<ConeDesc>(s.objects.at(0).shape);
  EXPECT_EQ(a.baseRadius, 1);
  EXPECT_EQ(a.capRadius, 0);
  EXPECT_FALSE(a.open);
  const auto& b = std::get<ConeDesc>(s.objects.at(1).shape);
  expectVec(b.cap, 0, 1, 0);
  EXPECT_EQ(b.baseRadius, 0);
  EXPECT_EQ(b.capRadius, 0.5);
  EXPECT_TRUE(b.open);
}

TEST(XmlLoader, DiscWithDefaultsAndHole) {
  const SceneDesc s = load(inScene("<disc center=\"1 2 3\" radius=\"2\"/>\n"
                                   "<disc center=\"0 0 0\" normal=\"0 0 -1\" radius=\"2\" hole_radius=\"0.5\"/>"));
  const auto& a = std::get<DiscDesc>(s.objects.at(0).shape);
  expectVec(a.center, 1, 2, 3);
  expectVec(a.normal, 0, 1, 0);
  EXPECT_EQ(a.radius, 2);
  EXPECT_EQ(a.holeRadius, 0);
  const auto& b = std::get<DiscDesc>(s.objects.at(1).shape);
  expectVec(b.normal, 0, 0, -1);
  EXPECT_EQ(b.holeRadius, 0.5);
}

TEST(XmlLoader, TriangleAndSmoothTriangle) {
  const SceneDesc s = load(inScene(
      "<triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\"/>\n"
      "<smooth_triangle p1=\"0 0 0\" n1=\"0 0 -1\" p2=\"1 0 0\" n2=\"0 0.5 -1\" p3=\"0 1 0\" n3=\"1 0 -1\"/>"));
  const auto& t = std::get<TriangleDesc>(s.objects.at(0).shape);
  expectVec(t.p1, 0, 0, 0);
  expectVec(t.p2, 1, 0, 0);
  expectVec(t.p3, 0, 1, 0);
  EXPECT_EQ(t.loc.line, 2);
  const SmoothTriangleDesc& st = *std::get<SmoothTriangleRef>(s.objects.at(1).shape);
  expectVec(st.n1, 0, 0, -1);
  expectVec(st.p2, 1, 0, 0);
  expectVec(st.n2, 0, 0.5, -1);
  expectVec(st.p3, 0, 1, 0);
  expectVec(st.n3, 1, 0, -1);
  EXPECT_EQ(st.loc.line, 3);
  EXPECT_STREQ(shapeName(s.objects[1].shape), "smooth_triangle");
}

TEST(XmlLoader, MeshChildrenInOrderWithLinesTransformsAndMaterial) {
  const SceneDesc s = load(inScene(
      "<mesh no_shadow=\"true\">\n"
      "  <triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\"/>\n"
      "  <smooth_triangle p1=\"0 0 1\" n1=\"0 0 1\" p2=\"1 0 1\" n2=\"0 0 1\" p3=\"0 1 1\" n3=\"0 0 1\"/>\n"
      "  <pigment color=\"0.5\"/>\n"
      "  <triangle p1=\"0 0 2\" p2=\"1 0 2\" p3=\"0 1 2\"/>\n"
      "  <scale v=\"2\"/>\n"
      "</mesh>"));
  const ObjectDesc& o = s.objects.at(0);
  const auto& m = std::get<MeshDesc>(o.shape);
  ASSERT_EQ(m.triangles.size(), 2u);
  ASSERT_EQ(m.smoothTriangles.size(), 1u);
  EXPECT_EQ(m.triangles[0].loc.line, 3);
  EXPECT_EQ(m.triangles[1].loc.line, 6);
  expectVec(m.triangles[1].p1, 0, 0, 2);
  EXPECT_EQ(m.smoothTriangles[0].loc.line, 4);
  expectVec(m.smoothTriangles[0].p2, 1, 0, 1);
  expectColor(o.material.pigment.color.rgb, 0.5, 0.5, 0.5);
  ASSERT_EQ(o.transforms.steps.size(), 1u);
  EXPECT_TRUE(o.noShadow);
  EXPECT_STREQ(shapeName(o.shape), "mesh");
}

// ---------------------------------------------------------------- values

TEST(XmlLoader, VectorsWithCommasOrSpaces) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"1,2,3\" radius=\"1\"/>\n"
      "<sphere center=\"1, 2, 3\" radius=\"1\"/>\n"
      "<sphere center=\"  1 \t 2\n3  \" radius=\"1\"/>\n"
      "<sphere center=\"1 ,2 ,3\" radius=\"1\"/>\n"
      "<sphere center=\"+1 2e0 .3e1\" radius=\"1\"/>\n"
      "<sphere center=\"-1.5 -0 1E2\" radius=\"1\"/>"));
  ASSERT_EQ(s.objects.size(), 6u);
  for (int i = 0; i < 5; ++i) {
    SCOPED_TRACE(i);
    expectVec(std::get<SphereDesc>(s.objects[size_t(i)].shape).center, 1, 2, 3);
  }
  const Vec3 c = std::get<SphereDesc>(s.objects[5].shape).center;
  expectVec(c, -1.5, 0, 100);
  EXPECT_TRUE(std::signbit(c.y));
  // The third sphere's attribute spans a line break, which moves the fourth to line 6.
  EXPECT_EQ(s.objects[3].loc.line, 6);
}

TEST(XmlLoader, SingleNumberForScaleAndColours) {
  const SceneDesc s = load(inScene(
      "<background color=\"0.25\"/>\n"
      "<global_settings ambient_light=\"0.5\"/>\n"
      "<light_source location=\"0 0 0\" color=\"2\"/>\n"
      "<sphere center=\"0 0 0\" radius=\"1\">\n"
      "  <finish ambient=\"0.2\" emission=\"0.1\" reflection=\"0.3\"/>\n"
      "  <interior fade_color=\"0.7\"/>\n"
      "  <scale v=\"3\"/>\n"
      "  <scale v=\"1 2 3\"/>\n"
      "</sphere>"));
  expectColor(s.background, 0.25, 0.25, 0.25);
  expectColor(s.globals.ambientLight, 0.5, 0.5, 0.5);
  expectColor(s.lights.at(0).color, 2, 2, 2);
  const ObjectDesc& o = s.objects.at(0);
  expectColor(o.material.finish->ambient, 0.2, 0.2, 0.2);
  expectColor(o.material.finish->emission, 0.1, 0.1, 0.1);
  expectColor(o.material.finish->reflection.min, 0.3, 0.3, 0.3);
  expectColor(o.material.finish->reflection.max, 0.3, 0.3, 0.3);
  expectColor(o.material.interior->fadeColor, 0.7, 0.7, 0.7);
  ASSERT_EQ(o.transforms.steps.size(), 2u);
  expectVec(o.transforms.steps[0].v, 3, 3, 3);
  expectVec(o.transforms.steps[1].v, 1, 2, 3);
}

// Numbers are read where they lie when they are plain, word by word otherwise: a colour of one
// or three numbers in any spacing reads the same either way, and anything else gets the
// word-by-word path's message.
TEST(XmlLoader, ColoursOfOneOrThreeNumbersAndTheirErrors) {
  const SceneDesc s = load(inScene("<background color=\" +-1,, 2\t+.5e1 \"/>"));
  expectColor(s.background, -1, 2, 5);
  expectColor(load(inScene("<background color=\"\n+0.5 \"/>")).background, 0.5, 0.5, 0.5);
  const std::string at = "t.xml:2: error: background: attribute 'color'";
  for (const auto& [value, want] : std::vector<std::pair<std::string, std::string>>{
           {"1 2", " must be a vector of 3 numbers, got \"1 2\""},
           {"1 2 3 4", " must be a vector of 3 numbers, got \"1 2 3 4\""},
           {"", " must be a vector of 3 numbers, got \"\""},
           {"1.5x 0 0", ": \"1.5x\" is not a number"},
           {"0 0 0x10", ": \"0x10\" is not a number"},
           {"+ 1 2", ": \"+\" is not a number"},
           {"inf 0 0", ": inf is not a finite number"},
           {"0 nan 0", ": nan is not a finite number"},
           {"1e400 0 0", ": 1e400 is out of range (at most 1e15 in magnitude)"},
           {"2e15", ": 2e15 is out of range (at most 1e15 in magnitude)"}})
    EXPECT_SCENE_ERROR(inScene("<background color=\"" + value + "\"/>"), at + want);
}

TEST(XmlLoader, TinyNumbersUnderflowToZeroButHugeOnesAreRefused) {
  const SceneDesc s = load(inScene("<sphere center=\"1e-400 5e-324 1e-300\" radius=\"1e15\"/>"));
  const auto& sp = std::get<SphereDesc>(s.objects.at(0).shape);
  EXPECT_EQ(sp.center.x, 0);
  EXPECT_EQ(sp.center.y, 5e-324);
  EXPECT_EQ(sp.center.z, 1e-300);
  EXPECT_EQ(sp.radius, 1e15);
  // Finite but beyond 1e15 (where squares inside the renderer could overflow), and beyond a double.
  for (const char* big : {"1.000000000000001e15", "-1e16", "1.7976931348623157e308", "-1e308", "1.8e308"})
    EXPECT_SCENE_ERROR(inScene(std::string("<sphere center=\"0 0 0\" radius=\"") + big + "\"/>"),
                       std::string("t.xml:2: error: sphere: attribute 'radius': ") + big +
                           " is out of range (at most 1e15 in magnitude)");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"0.00001e-400\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius' must be positive, got 0.00001e-400");
}

TEST(XmlLoader, NamedMaterialsAreCopiedIntoObjects) {
  const SceneDesc s = load(inScene(
      "<material name=\"red\"><pigment color=\"1 0 0\"/><finish phong=\"0.5\"/></material>\n"
      "<material name=\"glass\"><pigment color=\"1\" filter=\"0.9\"/><interior ior=\"1.5\"/></material>\n"
      "<sphere center=\"0 0 0\" radius=\"1\" material=\"glass\"/>\n"
      "<box corner1=\"0 0 0\" corner2=\"1 1 1\" material=\"red\"><translate v=\"1 0 0\"/></box>\n"
      "<sphere center=\"0 0 0\" radius=\"1\"/>"));
  ASSERT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.materials[0].name, "red");
  EXPECT_EQ(s.materials[1].name, "glass");
  ASSERT_EQ(s.objects.size(), 3u);
  const ObjectDesc& a = s.objects[0];
  EXPECT_EQ(a.namedMaterial, 1);
  EXPECT_EQ(a.material.name, "glass");
  EXPECT_EQ(a.material.pigment.color.filter, 0.9);
  EXPECT_EQ(a.material.interior->ior, 1.5);
  EXPECT_EQ(a.material.loc.line, 3);  // where the material was defined
  const ObjectDesc& b = s.objects[1];
  EXPECT_EQ(b.namedMaterial, 0);
  EXPECT_EQ(b.material.name, "red");
  expectColor(b.material.pigment.color.rgb, 1, 0, 0);
  EXPECT_EQ(b.material.finish->phong, 0.5);
  EXPECT_EQ(b.transforms.steps.size(), 1u);
  EXPECT_EQ(s.objects[2].namedMaterial, -1);
}

TEST(XmlLoader, TransformsAreKeptInTheOrderWritten) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"0 0 0\" radius=\"1\">\n"
      "  <translate v=\"1 0 0\"/>\n"
      "  <scale v=\"2\"/>\n"
      "  <rotate v=\"0 90 0\"/>\n"
      "  <matrix v=\"1 0 0  0 1 0  0.5 0 1  4 5 6\"/>\n"
      "</sphere>"));
  const TransformList& t = s.objects.at(0).transforms;
  ASSERT_EQ(t.steps.size(), 4u);
  EXPECT_EQ(t.steps[0].kind, TransformStep::Kind::Translate);
  expectVec(t.steps[0].v, 1, 0, 0);
  EXPECT_EQ(t.steps[0].loc.line, 3);
  EXPECT_EQ(t.steps[1].kind, TransformStep::Kind::Scale);
  expectVec(t.steps[1].v, 2, 2, 2);
  EXPECT_EQ(t.steps[1].loc.line, 4);
  EXPECT_EQ(t.steps[2].kind, TransformStep::Kind::Rotate);
  expectVec(t.steps[2].v, 0, 90, 0);
  EXPECT_EQ(t.steps[3].kind, TransformStep::Kind::Matrix);
  const std::array<double, 12> want{1, 0, 0, 0, 1, 0, 0.5, 0, 1, 4, 5, 6};
  EXPECT_EQ(t.steps[3].matrix, want);
  EXPECT_EQ(t.steps[3].loc.line, 6);
  // Applied in that order: (0,0,0) -> (1,0,0) -> (2,0,0) -> (0,0,-2) -> (0 + 0.5*-2 + 4, 5, -2 + 6).
  expectNear(t.combined().applyPoint({0, 0, 0}), 3, 5, 4);
}

TEST(XmlLoader, TransformOrderMattersAndRotationIsLeftHanded) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"0 0 0\" radius=\"1\"><scale v=\"2\"/><translate v=\"1 0 0\"/></sphere>\n"
      "<sphere center=\"0 0 0\" radius=\"1\"><translate v=\"1 0 0\"/><scale v=\"2\"/></sphere>\n"
      "<sphere center=\"0 0 0\" radius=\"1\"><rotate v=\"0 90 0\"/></sphere>\n"
      "<sphere center=\"0 0 0\" radius=\"1\"><rotate v=\"90 0 0\"/></sphere>\n"
      "<sphere center=\"0 0 0\" radius=\"1\"><rotate v=\"0 0 90\"/></sphere>\n"
      "<sphere center=\"0 0 0\" radius=\"1\"><rotate v=\"90 90 0\"/></sphere>"));
  ASSERT_EQ(s.objects.size(), 6u);
  const Vec3 x{1, 0, 0}, y{0, 1, 0};
  expectNear(s.objects[0].transforms.combined().applyPoint(x), 3, 0, 0);
  expectNear(s.objects[1].transforms.combined().applyPoint(x), 4, 0, 0);
  expectNear(s.objects[2].transforms.combined().applyPoint(x), 0, 0, -1);  // +x to -z
  expectNear(s.objects[3].transforms.combined().applyPoint(y), 0, 0, 1);   // +y to +z
  expectNear(s.objects[4].transforms.combined().applyPoint(x), 0, 1, 0);   // +x to +y
  // x first, then y: +y -> (x 90) +z -> (y 90) +x.
  expectNear(s.objects[5].transforms.combined().applyPoint(y), 1, 0, 0);
}

TEST(XmlLoader, MatrixIsPovRaysRowVectorForm) {
  const SceneDesc s = load(inScene(
      "<sphere center=\"0 0 0\" radius=\"1\"><matrix v=\"0,1,0, -1,0,0, 0,0,1, 7,8,9\"/></sphere>"));
  const Affine a = s.objects.at(0).transforms.combined();
  // x' = x*a + y*d + z*g + j, y' = x*b + y*e + z*h + k: (1,0,0) -> (0,1,0) + (7,8,9).
  expectNear(a.applyPoint({1, 0, 0}), 7, 9, 9);
  expectNear(a.applyPoint({0, 1, 0}), 6, 8, 9);
}

TEST(XmlLoader, IntegersAndBooleans) {
  const SceneDesc s = load(inScene(
      "<image width=\"1\" height=\"65536\"/>\n"
      "<light_source location=\"0 0 0\"><area_light axis1=\"1 0 0\" axis2=\"0 1 0\" size1=\"1024\" size2=\"1\" "
      "adaptive=\"0\" circular=\"false\" orient=\"false\"/></light_source>\n"
      "<cylinder base=\"0 0 0\" cap=\"0 1 0\" radius=\"1\" open=\"false\"/>"));
  EXPECT_EQ(s.image->width, 1);
  EXPECT_EQ(s.image->height, 65536);
  EXPECT_EQ(s.lights.at(0).area->size1, 1024);
  EXPECT_EQ(s.lights.at(0).area->adaptive, 0);
  EXPECT_FALSE(s.lights.at(0).area->circular);
  EXPECT_FALSE(std::get<CylinderDesc>(s.objects.at(0).shape).open);
}

TEST(XmlLoader, EntitiesInAttributesAreDecoded) {
  // The material name itself may not hold '&', so the entity only proves it is decoded.
  EXPECT_SCENE_ERROR(inScene("<material name=\"a&amp;b\"/>"),
                     "t.xml:2: error: material: material names use letters, digits and '_' only, got \"a&b\"");
}

TEST(XmlLoader, LoadSceneFileReadsFilesAndReportsMissingOnes) {
  try {
    loadSceneFile("/nonexistent-dir/none.xml");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/nonexistent-dir/none.xml: error: cannot read scene: No such file or directory");
    EXPECT_EQ(e.code(), ExitCode::SceneError);
  }
  try {
    loadSceneFile("/");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), "/: error: cannot read scene: it is a directory");
  }
}

// ---------------------------------------------------------------- errors: structure

TEST(XmlLoader, ErrorUnknownElement) {
  EXPECT_SCENE_ERROR(inScene("<sphre center=\"0 0 0\" radius=\"1\"/>"),
                     "t.xml:2: error: sphre: unknown element (expected camera, light_source, material, an object, ...)");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\">\n<spot/></light_source>"),
                     "t.xml:3: error: spot: unknown element inside <light_source> (expected spotlight or area_light)");
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\">\n<texture/></material>"),
                     "t.xml:3: error: texture: unknown element inside <material> (expected pigment, finish or interior)");
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\"><pigment>\n<checkers/></pigment></material>"),
                     "t.xml:3: error: checkers: unknown element inside <pigment> (expected checker or a transform)");
  EXPECT_SCENE_ERROR(inScene("<plane><finish>\n<phong/></finish></plane>"),
                     "t.xml:3: error: phong: unknown element inside <finish> (expected reflection)");
  EXPECT_SCENE_ERROR(inScene("<camera>\n<look_at/></camera>"),
                     "t.xml:3: error: look_at: unknown element inside <camera> (expected a transform)");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\">\n<triangle/></sphere>"),
                     "t.xml:3: error: triangle: unknown element inside <sphere>");
  EXPECT_SCENE_ERROR(inScene("<mesh>\n<sphere/></mesh>"), "t.xml:3: error: sphere: unknown element inside <mesh>");
  EXPECT_SCENE_ERROR(inScene("<plane><scale v=\"2\">\n<x/></scale></plane>"),
                     "t.xml:3: error: x: unexpected element inside <scale>");
  EXPECT_SCENE_ERROR(inScene("<image width=\"1\" height=\"1\">\n<x/></image>"),
                     "t.xml:3: error: x: unexpected element inside <image>");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\"><spotlight>\n<x/></spotlight></light_source>"),
                     "t.xml:3: error: x: unexpected element inside <spotlight>");
}

TEST(XmlLoader, ErrorUnknownAttribute) {
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\" color=\"1 0 0\"/>"),
                     "t.xml:2: error: sphere: unknown attribute 'color'");
  EXPECT_SCENE_ERROR("<scene version=\"1\"/>", "t.xml:1: error: scene: unknown attribute 'version'");
  EXPECT_SCENE_ERROR(inScene("<camera location=\"0 0 0\" fov=\"60\"/>"), "t.xml:2: error: camera: unknown attribute 'fov'");
  EXPECT_SCENE_ERROR(inScene("<plane><finish phong=\"1\" phongsize=\"2\"/></plane>"),
                     "t.xml:2: error: finish: unknown attribute 'phongsize' (did you mean 'phong_size'?)");
  EXPECT_SCENE_ERROR(inScene("<plane><scale v=\"2\" w=\"1\"/></plane>"), "t.xml:2: error: scale: unknown attribute 'w'");
  EXPECT_SCENE_ERROR(inScene("<plane><pigment><checker color3=\"1\"/></pigment></plane>"),
                     "t.xml:2: error: checker: unknown attribute 'color3' (did you mean 'color1'?)");
  // Unknown attributes are reported first, so a misspelt required one is named as it is
  // written (not as the missing one), with the known name it is closest to.
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radus=\"1\"/>"),
                     "t.xml:2: error: sphere: unknown attribute 'radus' (did you mean 'radius'?)");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"-1\" colour=\"1\"/>"),
                     "t.xml:2: error: sphere: unknown attribute 'colour'");
  // Known at the top level, not inside a mesh.
  EXPECT_SCENE_ERROR(inScene("<mesh><triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\" no_shadow=\"true\"/></mesh>"),
                     "t.xml:2: error: triangle: unknown attribute 'no_shadow'");
  // An unknown element is reported as such, not by its attributes.
  EXPECT_SCENE_ERROR(inScene("<sphre centre=\"0 0 0\"/>"),
                     "t.xml:2: error: sphre: unknown element (expected camera, light_source, material, an object, ...)");
}

TEST(XmlLoader, ErrorMissingRequiredAttribute) {
  EXPECT_SCENE_ERROR(inScene("<sphere radius=\"1\"/>"), "t.xml:2: error: sphere: missing required attribute 'center'");
  EXPECT_SCENE_ERROR(inScene("<light_source/>"), "t.xml:2: error: light_source: missing required attribute 'location'");
  EXPECT_SCENE_ERROR(inScene("<image width=\"10\"/>"), "t.xml:2: error: image: missing required attribute 'height'");
  EXPECT_SCENE_ERROR(inScene("<material/>"), "t.xml:2: error: material: missing required attribute 'name'");
  EXPECT_SCENE_ERROR(inScene("<box corner1=\"0 0 0\"/>"), "t.xml:2: error: box: missing required attribute 'corner2'");
  EXPECT_SCENE_ERROR(inScene("<cylinder base=\"0 0 0\" cap=\"0 1 0\"/>"),
                     "t.xml:2: error: cylinder: missing required attribute 'radius'");
  EXPECT_SCENE_ERROR(inScene("<cone base=\"0 0 0\"/>"), "t.xml:2: error: cone: missing required attribute 'cap'");
  EXPECT_SCENE_ERROR(inScene("<disc center=\"0 0 0\"/>"), "t.xml:2: error: disc: missing required attribute 'radius'");
  EXPECT_SCENE_ERROR(inScene("<triangle p1=\"0 0 0\" p2=\"1 0 0\"/>"),
                     "t.xml:2: error: triangle: missing required attribute 'p3'");
  EXPECT_SCENE_ERROR(inScene("<smooth_triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\" n2=\"0 0 1\" n3=\"0 0 1\"/>"),
                     "t.xml:2: error: smooth_triangle: missing required attribute 'n1'");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\"><area_light axis1=\"1 0 0\"/></light_source>"),
                     "t.xml:2: error: area_light: missing required attribute 'axis2'");
  EXPECT_SCENE_ERROR(inScene("<plane><rotate/></plane>"), "t.xml:2: error: rotate: missing required attribute 'v'");
  EXPECT_SCENE_ERROR(inScene("<plane><scale/></plane>"), "t.xml:2: error: scale: missing required attribute 'v'");
  EXPECT_SCENE_ERROR(inScene("<plane><matrix/></plane>"), "t.xml:2: error: matrix: missing required attribute 'v'");
}

TEST(XmlLoader, ErrorWrongType) {
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"zero\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center' must be a vector of 3 numbers, got \"zero\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 zero\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center': \"zero\" is not a number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center' must be a vector of 3 numbers, got \"0 0\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0 0\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center' must be a vector of 3 numbers, got \"0 0 0 0\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"&lt;0, 0, 0&gt;\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center': \"<0\" is not a number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1 2\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius' must be one number, got \"1 2\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius' must be one number, got \"\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1cm\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius': \"1cm\" is not a number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"0x10\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius': \"0x10\" is not a number");
  EXPECT_SCENE_ERROR(inScene("<background color=\"1 0\"/>"),
                     "t.xml:2: error: background: attribute 'color' must be a vector of 3 numbers, got \"1 0\"");
  EXPECT_SCENE_ERROR(inScene("<plane><translate v=\"2\"/></plane>"),
                     "t.xml:2: error: translate: attribute 'v' must be a vector of 3 numbers, got \"2\"");
  EXPECT_SCENE_ERROR(inScene("<plane><rotate v=\"90\"/></plane>"),
                     "t.xml:2: error: rotate: attribute 'v' must be a vector of 3 numbers, got \"90\"");
  EXPECT_SCENE_ERROR(inScene("<plane><matrix v=\"1 0 0 0 1 0 0 0 1 0 0\"/></plane>"),
                     "t.xml:2: error: matrix: attribute 'v' must hold 12 numbers, got 11");
  EXPECT_SCENE_ERROR(inScene("<plane><matrix v=\"1 0 0 0 1 0 0 0 1 0 0 x\"/></plane>"),
                     "t.xml:2: error: matrix: attribute 'v': \"x\" is not a number");
  EXPECT_SCENE_ERROR(inScene("<image width=\"1.5\" height=\"10\"/>"),
                     "t.xml:2: error: image: attribute 'width' must be an integer, got \"1.5\"");
  EXPECT_SCENE_ERROR(inScene("<image width=\"ten\" height=\"10\"/>"),
                     "t.xml:2: error: image: attribute 'width' must be an integer, got \"ten\"");
  EXPECT_SCENE_ERROR(inScene("<global_settings max_trace_level=\"0\"/>"),
                     "t.xml:2: error: global_settings: attribute 'max_trace_level' must be an integer from 1 to 256, got 0");
}

TEST(XmlLoader, ErrorNaNInfAndOutOfRange) {
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 nan 0\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center': nan is not a finite number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"NaN\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius': NaN is not a finite number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"inf\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius': inf is not a finite number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"-infinity 0 0\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center': -infinity is not a finite number");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1e999\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius': 1e999 is out of range (at most 1e15 in magnitude)");
  // Out of range where no other check would catch the value (it used to read as 0).
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"-1e999 0 0\" radius=\"1\"/>"),
                     "t.xml:2: error: sphere: attribute 'center': -1e999 is out of range (at most 1e15 in magnitude)");
  EXPECT_SCENE_ERROR(inScene("<plane><translate v=\"0 1e99999999999999999999 0\"/></plane>"),
                     "t.xml:2: error: translate: attribute 'v': 1e99999999999999999999 is out of range (at most 1e15 in magnitude)");
  EXPECT_SCENE_ERROR(inScene("<plane><matrix v=\"1 0 0 0 1 0 0 0 1 0 0 1e400\"/></plane>"),
                     "t.xml:2: error: matrix: attribute 'v': 1e400 is out of range (at most 1e15 in magnitude)");
  EXPECT_SCENE_ERROR(inScene("<image width=\"99999999999999999999\" height=\"1\"/>"),
                     "t.xml:2: error: image: attribute 'width' must be an integer from 1 to 65536, got 99999999999999999999");
}

TEST(XmlLoader, ErrorNegativeOrZeroWhereNotAllowed) {
  // The example from the format's documentation.
  EXPECT_SCENE_ERROR("<scene>\n<sphere center=\"0 0 0\" radius=\"-1\"/>\n</scene>",
                     "t.xml:2: error: sphere: attribute 'radius' must be positive, got -1");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"0\"/>"),
                     "t.xml:2: error: sphere: attribute 'radius' must be positive, got 0");
  EXPECT_SCENE_ERROR(inScene("<cone base=\"0 0 0\" base_radius=\"-1\" cap=\"0 1 0\"/>"),
                     "t.xml:2: error: cone: attribute 'base_radius' must not be negative, got -1");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\" fade_distance=\"-2\"/>"),
                     "t.xml:2: error: light_source: attribute 'fade_distance' must not be negative, got -2");
  EXPECT_SCENE_ERROR(inScene("<plane><finish roughness=\"0\"/></plane>"),
                     "t.xml:2: error: finish: attribute 'roughness' must be positive, got 0");
  EXPECT_SCENE_ERROR(inScene("<plane><interior ior=\"-1.5\"/></plane>"),
                     "t.xml:2: error: interior: attribute 'ior' must be positive, got -1.5");
  EXPECT_SCENE_ERROR(inScene("<plane><finish><reflection exponent=\"0\"/></finish></plane>"),
                     "t.xml:2: error: reflection: attribute 'exponent' must be positive, got 0");
  EXPECT_SCENE_ERROR(inScene("<global_settings adc_bailout=\"-0.1\"/>"),
                     "t.xml:2: error: global_settings: attribute 'adc_bailout' must not be negative, got -0.1");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\"><spotlight tightness=\"-1\"/></light_source>"),
                     "t.xml:2: error: spotlight: attribute 'tightness' must not be negative, got -1");
  EXPECT_SCENE_ERROR(inScene("<plane normal=\"0 0 0\"/>"),
                     "t.xml:2: error: plane: attribute 'normal' must not be the zero vector");
  EXPECT_SCENE_ERROR(inScene("<camera direction=\"0, 0, 0\"/>"),
                     "t.xml:2: error: camera: attribute 'direction' must not be the zero vector");
  EXPECT_SCENE_ERROR(inScene("<image width=\"0\" height=\"10\"/>"),
                     "t.xml:2: error: image: attribute 'width' must be an integer from 1 to 65536, got 0");
  EXPECT_SCENE_ERROR(inScene("<image width=\"10\" height=\"65537\"/>"),
                     "t.xml:2: error: image: attribute 'height' must be an integer from 1 to 65536, got 65537");
  EXPECT_SCENE_ERROR(
      inScene("<light_source location=\"0 0 0\"><area_light axis1=\"1 0 0\" axis2=\"0 1 0\" size1=\"0\"/></light_source>"),
      "t.xml:2: error: area_light: attribute 'size1' must be an integer from 1 to 1024, got 0");
  EXPECT_SCENE_ERROR(
      inScene("<light_source location=\"0 0 0\"><area_light axis1=\"1 0 0\" axis2=\"0 1 0\" adaptive=\"101\"/>"
              "</light_source>"),
      "t.xml:2: error: area_light: attribute 'adaptive' must be an integer from 0 to 100, got 101");
}

TEST(XmlLoader, ErrorDegenerateShapesAndCamera) {
  EXPECT_SCENE_ERROR(inScene("<cylinder base=\"1 1 1\" cap=\"1,1,1\" radius=\"1\"/>"),
                     "t.xml:2: error: cylinder: base and cap must differ");
  EXPECT_SCENE_ERROR(inScene("<cone base=\"0 0 0\" cap=\"0 0 0\"/>"), "t.xml:2: error: cone: base and cap must differ");
  EXPECT_SCENE_ERROR(inScene("<cone base=\"0 0 0\" base_radius=\"0\" cap=\"0 1 0\"/>"),
                     "t.xml:2: error: cone: base_radius and cap_radius cannot both be 0");
  EXPECT_SCENE_ERROR(inScene("<disc center=\"0 0 0\" radius=\"1\" hole_radius=\"1\"/>"),
                     "t.xml:2: error: disc: hole_radius must be smaller than radius");
  EXPECT_SCENE_ERROR(inScene("<mesh>\n</mesh>"), "t.xml:2: error: mesh: a mesh needs at least one triangle or smooth_triangle");
  EXPECT_SCENE_ERROR(inScene("<smooth_triangle p1=\"0 0 0\" n1=\"0 0 0\" p2=\"1 0 0\" n2=\"0 0 1\" p3=\"0 1 0\" "
                             "n3=\"0 0 1\"/>"),
                     "t.xml:2: error: smooth_triangle: attribute 'n1' must not be the zero vector");
  EXPECT_SCENE_ERROR(inScene("<camera location=\"1 2 3\" look_at=\"1 2 3\"/>"),
                     "t.xml:2: error: camera: look_at must differ from location");
  EXPECT_SCENE_ERROR(inScene("<camera angle=\"180\"/>"),
                     "t.xml:2: error: camera: attribute 'angle' must lie between 0 and 180 degrees");
  EXPECT_SCENE_ERROR(inScene("<camera angle=\"0\"/>"),
                     "t.xml:2: error: camera: attribute 'angle' must lie between 0 and 180 degrees");
  EXPECT_SCENE_ERROR(inScene("<camera up=\"2 0 0\"/>"), "t.xml:2: error: camera: up and right must not be parallel");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\"><spotlight radius=\"91\"/></light_source>"),
                     "t.xml:2: error: spotlight: radius and falloff must lie between 0 and 90 degrees");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 1\"><spotlight/></light_source>"),
                     "t.xml:2: error: spotlight: point_at must differ from the light's location");
}

// Nearly equal is as bad as equal when rounding, not the scene, would decide the direction
// (issue 29 item 1: before, these gave NaN pixels or a blank image with exit 0).
TEST(XmlLoader, ErrorNearlyDegenerateVectors) {
  EXPECT_SCENE_ERROR(inScene("<camera location=\"0 2 -5\" look_at=\"1e-170 2 -5\"/>"),
                     "t.xml:2: error: camera: look_at must differ from location by more than 1e-12 of their "
                     "coordinates (5): they are 1e-170 apart, a direction rounding decides");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"2 5 -3\"><spotlight point_at=\"2.0000000000000004 5 -3\"/>"
                             "</light_source>"),
                     "t.xml:2: error: spotlight: point_at must differ from the light's location by more than 1e-12 "
                     "of their coordinates (5): they are 4.44e-16 apart, a direction rounding decides");
  EXPECT_SCENE_ERROR(inScene("<cylinder base=\"1 0 0\" cap=\"1 1e-170 0\" radius=\"1\"/>"),
                     "t.xml:2: error: cylinder: base and cap must differ by more than 1e-12 of their coordinates "
                     "(1): they are 1e-170 apart, a direction rounding decides");
  EXPECT_SCENE_ERROR(inScene("<cone base=\"0 0 0\" cap=\"0 1e-120 0\"/>"),
                     "t.xml:2: error: cone: base and cap must differ by more than 1e-100: they are 1e-120 apart");
  EXPECT_SCENE_ERROR(inScene("<camera up=\"0 1 0\" right=\"0 1 1e-14\"/>"),
                     "t.xml:2: error: camera: up and right must not be parallel");
  EXPECT_SCENE_ERROR(inScene("<disc center=\"0 0 0\" normal=\"0 1e-170 0\" radius=\"1\"/>"),
                     "t.xml:2: error: disc: attribute 'normal' is too short to give a direction: its components "
                     "are below 1e-100");
  // Far apart relative to their coordinates, however small: a scene a millionth the size.
  EXPECT_NO_THROW(loadSceneString(inScene("<camera location=\"0 6e-6 -1.4e-5\" look_at=\"0 1e-6 2e-6\"/>"
                                          "<cylinder base=\"0 0 0\" cap=\"0 1e-90 0\" radius=\"1e-90\"/>"),
                                  "t.xml"));
}

TEST(XmlLoader, ErrorZeroScaleAndSingularTransforms) {
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\">\n<scale v=\"1 0 1\"/></sphere>"),
                     "t.xml:3: error: scale: a scale factor of zero flattens the object");
  EXPECT_SCENE_ERROR(inScene("<plane><scale v=\"0\"/></plane>"),
                     "t.xml:2: error: scale: a scale factor of zero flattens the object");
  EXPECT_SCENE_ERROR(inScene("<plane>\n<matrix v=\"1 0 0  2 0 0  0 0 1  0 0 0\"/></plane>"),
                     "t.xml:3: error: matrix: the matrix is singular");
  // Each step is fine; together they squash z to 1e-16, below the range.
  const std::string range =
      "its transforms together scale by more than 1e15 or less than 1e-15, or move by more than 1e15";
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\">\n<scale v=\"1 1 1e-8\"/>\n"
                             "<scale v=\"1 1 1e-8\"/></sphere>"),
                     "t.xml:2: error: sphere: " + range);
  EXPECT_SCENE_ERROR(inScene("<camera><scale v=\"1 1 1e-8\"/><scale v=\"1 1 1e-8\"/></camera>"),
                     "t.xml:2: error: camera: " + range);
  EXPECT_SCENE_ERROR(inScene("<plane><pigment><scale v=\"1e-8 1 1\"/><scale v=\"1e-8 1 1\"/></pigment></plane>"),
                     "t.xml:2: error: pigment: " + range);
  EXPECT_SCENE_ERROR(inScene("<plane><rotate v=\"0 0 45\"/><matrix v=\"1 1 0  1 1 0  0 0 1  0 0 0\"/></plane>"),
                     "t.xml:2: error: matrix: the matrix is singular");
}

// A scale far larger along one axis than the others is legal, as in POV-Ray (which refuses
// only a matrix whose determinant is 0): within the range of 1e-15 to 1e15 it loads, turned
// or not, as a step of its own or as a matrix. These were refused as singular.
TEST(XmlLoader, AnisotropicScalesLoad) {
  for (const char* t :
       {"<scale v=\"1e9 1 1\"/>", "<scale v=\"1 1e-7 1e-7\"/>", "<scale v=\"1e5 1e-5 1\"/>",
        "<matrix v=\"1e8 0 0  0 1e-8 0  0 0 1  0 0 0\"/>",
        "<rotate v=\"0 0 30\"/><scale v=\"1e12 1 1\"/><rotate v=\"20 0 0\"/>", "<scale v=\"1e15 1e-15 1\"/>"}) {
    SCOPED_TRACE(t);
    EXPECT_NO_THROW(
        loadSceneString(inScene(std::string("<sphere center=\"0 0 0\" radius=\"1\">") + t + "</sphere><camera>" + t +
                                "</camera><plane><pigment>" + t + "</pigment></plane>"),
                        "t.xml"));
  }
}

TEST(XmlLoader, ErrorElementsThatMayAppearOnlyOnce) {
  EXPECT_SCENE_ERROR("<scene>\n<camera/>\n<camera/>\n</scene>", "t.xml:3: error: camera: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<global_settings/>\n<global_settings/>"), "t.xml:3: error: global_settings: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<background/>\n<background/>"), "t.xml:3: error: background: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<image width=\"1\" height=\"1\"/>\n<image width=\"1\" height=\"1\"/>"),
                     "t.xml:3: error: image: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\"><spotlight/>\n<spotlight/></light_source>"),
                     "t.xml:3: error: spotlight: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\"><area_light axis1=\"1 0 0\" axis2=\"0 1 0\"/>\n"
                             "<area_light axis1=\"1 0 0\" axis2=\"0 1 0\"/></light_source>"),
                     "t.xml:3: error: area_light: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<plane><pigment/>\n<pigment/></plane>"), "t.xml:3: error: pigment: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\"><finish/>\n<finish/></material>"),
                     "t.xml:3: error: finish: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<plane><interior/>\n<interior/></plane>"), "t.xml:3: error: interior: may appear only once");
  EXPECT_SCENE_ERROR(inScene("<plane><pigment><checker/>\n<checker/></pigment></plane>"),
                     "t.xml:3: error: checker: may appear only once");
}

TEST(XmlLoader, ErrorMaterialReferencesAndNames) {
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\" material=\"glass\"/>"),
                     "t.xml:2: error: sphere: no material named 'glass' is defined before it");
  // A material must be defined before the objects that use it.
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\" material=\"m\"/>\n<material name=\"m\"/>"),
                     "t.xml:2: error: sphere: no material named 'm' is defined before it");
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\"/>\n<material name=\"m\"/>"),
                     "t.xml:3: error: material: material 'm' is already defined at line 2");
  EXPECT_SCENE_ERROR(inScene("<material name=\"my glass\"/>"),
                     "t.xml:2: error: material: material names use letters, digits and '_' only, got \"my glass\"");
  EXPECT_SCENE_ERROR(inScene("<material name=\"\"/>"),
                     "t.xml:2: error: material: material names use letters, digits and '_' only, got \"\"");
}

TEST(XmlLoader, ErrorInlineMaterialCombinedWithNamedOne) {
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\"/>\n<sphere center=\"0 0 0\" radius=\"1\" material=\"m\">\n"
                             "  <pigment color=\"1 0 0\"/>\n</sphere>"),
                     "t.xml:4: error: pigment: the object already uses material 'm'");
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\"/>\n<plane material=\"m\"><finish/></plane>"),
                     "t.xml:3: error: finish: the object already uses material 'm'");
  EXPECT_SCENE_ERROR(inScene("<material name=\"m\"/>\n<plane material=\"m\"><interior/></plane>"),
                     "t.xml:3: error: interior: the object already uses material 'm'");
}

TEST(XmlLoader, ErrorCheckerWithPigmentColourAndReflectionTwice) {
  EXPECT_SCENE_ERROR(inScene("<plane><pigment color=\"1 0 0\">\n<checker/></pigment></plane>"),
                     "t.xml:3: error: checker: a checker pigment takes its colours from <checker>, not from <pigment>");
  EXPECT_SCENE_ERROR(inScene("<plane><finish reflection=\"0.5\">\n<reflection min=\"0.1\"/></finish></plane>"),
                     "t.xml:3: error: reflection: give reflection either as an attribute or as an element, not both");
}

TEST(XmlLoader, ErrorBadBoolean) {
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\" shadowless=\"yes\"/>"),
                     "t.xml:2: error: light_source: attribute 'shadowless' must be true or false, got \"yes\"");
  EXPECT_SCENE_ERROR(inScene("<plane no_shadow=\"True\"/>"),
                     "t.xml:2: error: plane: attribute 'no_shadow' must be true or false, got \"True\"");
  EXPECT_SCENE_ERROR(inScene("<cylinder base=\"0 0 0\" cap=\"0 1 0\" radius=\"1\" open=\"1\"/>"),
                     "t.xml:2: error: cylinder: attribute 'open' must be true or false, got \"1\"");
  EXPECT_SCENE_ERROR(inScene("<plane><finish conserve_energy=\"\"/></plane>"),
                     "t.xml:2: error: finish: attribute 'conserve_energy' must be true or false, got \"\"");
}

TEST(XmlLoader, ErrorMalformedXml) {
  // The error is on the line of the closing tag that disagrees; the text names both lines.
  EXPECT_SCENE_ERROR("<scene>\n<sphere center=\"0 0 0\" radius=\"1\">\n</scene>",
                     "t.xml:3: error: xml: malformed XML (XML_ERROR_MISMATCHED_ELEMENT: <sphere> of line 2 is closed by </scene> on line 3: an element not closed, or closed with another name)");
  EXPECT_SCENE_ERROR("<scene>\n<sphere center=\"0 0 0\" center=\"1 1 1\" radius=\"1\"/>\n</scene>",
                     "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_ATTRIBUTE: an attribute given twice, without quotes or '=', or the file ends inside its value)");
  EXPECT_SCENE_ERROR("<scene>\n<sphere center=0 radius=\"1\"/>\n</scene>",
                     "t.xml:2: error: xml: malformed XML (XML_ERROR_PARSING_ATTRIBUTE: an attribute given twice, without quotes or '=', or the file ends inside its value)");
  const std::string parsing =
      "error: xml: malformed XML (XML_ERROR_PARSING: not XML, or the file ends before its elements are closed)";
  EXPECT_SCENE_ERROR("sphere { <0, 0, 0>, 1 }", "t.xml:1: " + parsing);
  EXPECT_SCENE_ERROR("<scene>\n<sphere/>\n", "t.xml:1: " + parsing);
}

TEST(XmlLoader, ErrorEmptyDocument) {
  EXPECT_SCENE_ERROR("", "t.xml:1: error: xml: the file is empty");
  EXPECT_SCENE_ERROR("  \n\t\n", "t.xml:1: error: xml: the file is empty");
  EXPECT_SCENE_ERROR("<?xml version=\"1.0\"?>\n<!-- nothing -->\n", "t.xml:1: error: scene: the file has no <scene> element");
}

TEST(XmlLoader, ErrorWrongRoot) {
  EXPECT_SCENE_ERROR("<?xml version=\"1.0\"?>\n<scena/>", "t.xml:2: error: scena: the root element must be <scene>");
  EXPECT_SCENE_ERROR("<sphere center=\"0 0 0\" radius=\"1\"/>", "t.xml:1: error: sphere: the root element must be <scene>");
}

TEST(XmlLoader, ErrorTextContent) {
  // The line is the text's own, not its element's: <scene> starts on line 1 of a file whose
  // stray text may be on line 900 (it was reported on line 1).
  EXPECT_SCENE_ERROR("<scene>\nhello\n</scene>", "t.xml:2: error: scene: unexpected text \"hello\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\"/>\n\n  \n  x\n<plane/>"),
                     "t.xml:5: error: scene: unexpected text \"x\"");
  EXPECT_SCENE_ERROR("<scene>\r\n<plane/>\r\n\r\n\xc2\xa0\r\n</scene>\r\n",
                     "t.xml:4: error: scene: unexpected text \"\\u00a0\"");  // shown, not invisible
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\">\n\n1</sphere>"),
                     "t.xml:4: error: sphere: unexpected text \"1\"");
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"1\">1</sphere>"),
                     "t.xml:2: error: sphere: unexpected text \"1\"");
  EXPECT_SCENE_ERROR(inScene("<camera>\n<translate v=\"0 0 0\">x</translate></camera>"),
                     "t.xml:3: error: translate: unexpected text \"x\"");
  EXPECT_SCENE_ERROR(inScene("<plane><pigment color=\"1 0 0\">red</pigment></plane>"),
                     "t.xml:2: error: pigment: unexpected text \"red\"");
  EXPECT_SCENE_ERROR(inScene("<light_source location=\"0 0 0\">on</light_source>"),
                     "t.xml:2: error: light_source: unexpected text \"on\"");
  EXPECT_SCENE_ERROR(inScene("<background color=\"1\"><![CDATA[x]]></background>"),
                     "t.xml:2: error: background: unexpected text \"x\"");
  // Before the root too (tinyxml2 keeps it there, and the file loaded): a second byte order
  // mark, or a stray word.
  EXPECT_SCENE_ERROR("junk<scene/>", "t.xml:1: error: xml: unexpected text \"junk\" outside the <scene> element");
  EXPECT_SCENE_ERROR("<!-- a scene -->\n\n  x\n<scene>\n</scene>",
                     "t.xml:3: error: xml: unexpected text \"x\" outside the <scene> element");
  EXPECT_SCENE_ERROR("\xef\xbb\xbf\xef\xbb\xbf<scene/>",
                     "t.xml:1: error: xml: unexpected text \"\\ufeff\" outside the <scene> element");
  EXPECT_NO_THROW(loadSceneString("\xef\xbb\xbf \n<!-- x -->\n<scene/>\n", "t.xml"));
  // Long text is cut to its first 20 characters, and "..." says so.
  EXPECT_SCENE_ERROR(inScene("<mesh><triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\">abcdefghijklmnopqrstuvwxyz"
                             "</triangle></mesh>"),
                     "t.xml:2: error: triangle: unexpected text \"abcdefghijklmnopqrst...\"");
}

TEST(XmlLoader, NothingIsHalfLoadedTheFirstErrorWins) {
  // The first problem in document order is reported, even with later ones present.
  EXPECT_SCENE_ERROR(inScene("<sphere center=\"0 0 0\" radius=\"-1\"/>\n<bogus/>"),
                     "t.xml:2: error: sphere: attribute 'radius' must be positive, got -1");
}

// ---------------------------------------------------------------- a big file, read in pieces by many threads

// The scene as text (sceneToXml: every value, and named materials by name) with every line
// number the loader keeps and every object's material index; or the error.
std::string outcomeOf(const std::string& xml, size_t pieceBytes, int threads, size_t* pieces = nullptr) {
  setThreadBudget(threads);
  std::string out;
  try {
    const SceneDesc s = loadSceneString(xml, "t.xml", {pieceBytes, pieces});
    out = sceneToXml(s) + "\nlines:";
    auto line = [&](const SourceLoc& loc) { out += " " + loc.file.str() + ":" + std::to_string(loc.line); };
    auto transforms = [&](const TransformList& t) {
      for (const TransformStep& step : t.steps) line(step.loc);
    };
    auto material = [&](const MaterialDesc& m) {
      for (const SourceLoc& loc : {m.loc, m.pigment.loc}) line(loc);
      transforms(m.pigment.transforms);
    };
    for (const SourceLoc& loc : {s.camera.loc, s.globals.loc, s.image ? s.image->loc : SourceLoc{}}) line(loc);
    transforms(s.camera.transforms);
    for (const LightDesc& l : s.lights) line(l.loc);
    for (const MaterialDesc& m : s.materials) material(m);
    for (const ObjectDesc& o : s.objects) {
      line(o.loc);
      out += " m" + std::to_string(o.namedMaterial);
      material(o.material);
      transforms(o.transforms);
      if (const auto* mesh = std::get_if<MeshDesc>(&o.shape)) {
        for (const TriangleDesc& t : mesh->triangles) line(t.loc);
        for (const SmoothTriangleDesc& t : mesh->smoothTriangles) line(t.loc);
      }
    }
  } catch (const Error& e) {
    out = std::string("error: ") + e.what();
  }
  setThreadBudget(0);
  return out;
}

constexpr size_t kWhole = std::numeric_limits<size_t>::max();

// `xml` read in pieces of a few sizes by 1, 2, 3 and 8 threads gives what the whole file
// parsed as one tree gives, which is returned.
std::string expectSameWithAnyThreads(const std::string& xml) {
  const std::string whole = outcomeOf(xml, kWhole, 1);
  for (size_t pieceBytes : {size_t(1), size_t(150), size_t(1000)})
    for (int threads : {1, 2, 3, 8}) {
      size_t pieces = 0;
      EXPECT_EQ(outcomeOf(xml, pieceBytes, threads, &pieces), whole)
          << "pieces of " << pieceBytes << " bytes, " << threads << " threads";
      if (whole.rfind("error: ", 0) != 0) {
        EXPECT_GT(pieces, 2u);
      }
    }
  return whole;
}

// Every kind of element, order-dependent ones (settings, named materials and references to
// them) spread through a file of many pieces.
std::string spreadScene() {
  std::string xml =
      "<?xml version=\"1.0\"?>\n<!-- pieces -->\n<scene>\n"
      "  <image width=\"64\" height=\"40\"/>\n"
      "  <light_source location=\"1 2 3\"/>\n"
      "  <material name=\"red\"><pigment color=\"1 0 0\"><scale v=\"2\"/></pigment><finish phong=\"0.5\"/></material>\n"
      "  <sphere center=\"0 0 0\" radius=\"1\" material=\"red\"/>\n";
  for (int i = 0; i < 60; ++i) {
    const std::string n = std::to_string(i);
    xml += "  <sphere center=\"" + n + ".125 0.1 -" + n + "\" radius=\"0.3333333333333333\">\n"
           "    <pigment color=\"0." + n + " 0.5 1e-3\"/>\n    <finish reflection=\"0.25\" diffuse=\"0.7\"/>\n"
           "    <rotate v=\"0 " + n + " 0\"/>\n  </sphere>\n";
    if (i == 7) xml += "  <camera location=\"0 1 -5\" look_at=\"0 0 0\"><translate v=\"0 1 0\"/></camera>\n";
    if (i == 13) xml += "  <global_settings max_trace_level=\"7\"/>\n  <background color=\"0.1 0.2 0.3\"/>\n";
    if (i == 20)
      xml += "  <mesh material=\"red\"><triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\"/>\n"
             "    <smooth_triangle p1=\"0 0 0\" n1=\"0 0 1\" p2=\"1 0 0\" n2=\"0 0 1\" p3=\"0 1 0\" n3=\"0 0 1\"/></mesh>\n";
    if (i == 25) xml += "  <light_source location=\"4 5 6\"><spotlight point_at=\"0 0 0\"/></light_source>\n";
    if (i == 31) xml += "  <material name=\"glass\"><pigment color=\"1 1 1\" filter=\"0.9\"/><interior ior=\"1.5\"/></material>\n";
    if (i > 31 && i % 5 == 0) xml += "  <box corner1=\"0 0 0\" corner2=\"1 1 1\" material=\"glass\"/>\n";
    if (i > 40 && i % 7 == 0) xml += "  <plane material=\"red\" no_shadow=\"true\"/>\n";
  }
  return xml + "</scene>\n";
}

TEST(XmlLoader, PiecesReadByAnyNumberOfThreadsGiveTheWholeFilesScene) {
  const std::string whole = expectSameWithAnyThreads(spreadScene());
  ASSERT_EQ(whole.rfind("error: ", 0), std::string::npos) << whole;
  const SceneDesc s = loadSceneString(spreadScene(), "t.xml", {kWhole});
  EXPECT_EQ(s.objects.size(), 70u);  // 61 spheres, a mesh, 5 boxes, 3 planes
  EXPECT_EQ(s.lights.size(), 2u);
  EXPECT_EQ(s.materials.size(), 2u);
  EXPECT_EQ(s.globals.maxTraceLevel, 7);
}

// The element of `xml` (spreadScene()) starting with `at` replaced by `with`.
std::string replaced(std::string xml, const std::string& at, const std::string& with) {
  const size_t i = xml.find(at);
  EXPECT_NE(i, std::string::npos) << at;
  return xml.replace(i, at.size(), with);
}

// The first error in file order wins, whichever piece a thread finished first, also when
// it depends on earlier pieces and a later piece has an error of its own.
TEST(XmlLoader, PiecesReadByAnyNumberOfThreadsGiveTheFirstError) {
  const std::string xml = spreadScene();
  const std::string lateError = replaced(xml, "<sphere center=\"59.125", "<sphere radus=\"1\" center=\"59.125");
  const std::string earlyError = replaced(xml, "<sphere center=\"3.125", "<sphere radus=\"1\" center=\"3.125");
  struct Case {
    std::string xml, want;
  };
  const std::vector<Case> cases{
      {lateError, "sphere: unknown attribute 'radus'"},
      // A second camera (the first is in an earlier piece), then an error of the sphere after it.
      {replaced(lateError, "<sphere center=\"40.125", "<camera/><sphere center=\"40.125"), "camera: may appear only once"},
      {replaced(lateError, "<sphere center=\"40.125", "<image width=\"1\" height=\"1\"/><sphere center=\"40.125"),
       "image: may appear only once"},
      {replaced(lateError, "<sphere center=\"40.125", "<background/><global_settings/><sphere center=\"40.125"),
       "background: may appear only once"},
      // A material taken (in an earlier piece), used (in a later one) before it is defined.
      {replaced(lateError, "<sphere center=\"40.125", "<material name=\"red\"/><sphere center=\"40.125"),
       "material: material 'red' is already defined at line 6"},
      {replaced(lateError, "<sphere center=\"20.125", "<sphere material=\"glass\" center=\"20.125"),
       "sphere: no material named 'glass' is defined before it"},
      {replaced(lateError, "<sphere center=\"20.125", "<sphere material=\"\" center=\"20.125"),
       "sphere: no material named '' is defined before it"},
      // The same element fails in two ways: the order-dependent check comes first.
      {replaced(lateError, "<sphere center=\"20.125", "<sphere material=\"nothing\" center=\"20.125"),
       "sphere: no material named 'nothing' is defined before it"},
      {replaced(lateError, "<sphere center=\"40.125", "<camera right=\"0 0 0\"/><sphere center=\"40.125"),
       "camera: may appear only once"},
      {replaced(lateError, "<sphere center=\"40.125", "<material name=\"glass\"><bogus/></material><sphere center=\"40.125"),
       "material: material 'glass' is already defined at line"},
      // An earlier error of a piece of its own wins over an order-dependent one after it.
      {replaced(earlyError, "<sphere center=\"40.125", "<camera/><sphere center=\"40.125"), "sphere: unknown attribute 'radus'"},
      {replaced(earlyError, "<sphere center=\"40.125", "<sphere material=\"nothing\" center=\"40.125"),
       "sphere: unknown attribute 'radus'"},
      // Malformed XML anywhere comes first.
      {replaced(earlyError, "</scene>", "<sphere></sphre></scene>"), "malformed XML"},
  };
  for (const Case& c : cases) {
    const std::string got = expectSameWithAnyThreads(c.xml);
    EXPECT_EQ(got.rfind("error: ", 0), 0u) << c.want;
    EXPECT_NE(got.find(c.want), std::string::npos) << got;
  }
}

// A material defined in one piece and used in later ones is the one object copies, and its
// index is the same.
TEST(XmlLoader, MaterialsUsedInLaterPiecesThanTheirDefinition) {
  std::string xml = "<scene>\n";
  for (int i = 0; i < 40; ++i) {
    const std::string n = std::to_string(i);
    xml += "<material name=\"m" + n + "\"><pigment color=\"0." + n + " 0 0\"/></material>\n";
    xml += "<sphere center=\"0 0 " + n + "\" radius=\"1\" material=\"m" + std::to_string(i / 2) + "\"/>\n";
  }
  xml += "</scene>\n";
  expectSameWithAnyThreads(xml);
  setThreadBudget(3);
  const SceneDesc s = loadSceneString(xml, "t.xml", {64});
  setThreadBudget(0);
  ASSERT_EQ(s.objects.size(), 40u);
  EXPECT_EQ(s.objects[39].namedMaterial, 19);
  EXPECT_EQ(s.objects[39].material.name, "m19");
  EXPECT_EQ(s.objects[39].material.loc.line, 2 + 2 * 19);
  EXPECT_EQ(s.objects[39].material.pigment.color.rgb.r, 0.19);
}

// A file big enough to be read into memory at once (SceneBytes, from 32 MB) and in pieces,
// whose pieces' text is given back as soon as each is read: the scene and the first error
// are still those of the whole parse, also when a late piece is malformed (the pieces' way
// then gives up after giving text back, and the file is read again) or a middle one fails.
TEST(XmlLoader, BigFileGivesBackItsTextAndStillGivesTheWholeParsesAnswer) {
  std::string body;
  for (int i = 0; i < 400000; ++i)
    body += "  <sphere center=\"" + std::to_string(i) + ".5 1 2\" radius=\"0.25\"><pigment color=\"0.5 0.25 1\"/></sphere>\n";
  ASSERT_GT(body.size(), size_t(32) << 20);
  const std::string valid = "<scene>\n<camera location=\"0 0 -5\"/>\n" + body + "</scene>\n";
  const std::string lateMalformed = "<scene>\n" + body + "<sphere></sphre>\n</scene>\n";
  std::string middleError = valid;
  middleError.replace(middleError.find("<sphere center=\"200000.5"), 7, "<sphere radus=\"1\"");
  const std::string path =
      (std::filesystem::temp_directory_path() / ("pvrt_big_file_" + std::to_string(::getpid()) + ".xml")).string();
  auto outcome = [](auto load) {
    try {
      return sceneToXml(load());
    } catch (const Error& e) {
      return std::string("error: ") + e.what();
    }
  };
  struct Case {
    const std::string* xml;
    size_t pieces;  // at least this many pieces read (0: none, the file was read whole)
  };
  for (const Case& c : {Case{&valid, 8}, Case{&lateMalformed, 0}, Case{&middleError, 0}}) {
    std::ofstream(path, std::ios::binary) << *c.xml;
    size_t pieces = 0;
    setThreadBudget(2);
    const std::string fromFile = outcome([&] { return loadSceneFile(path, {size_t(1) << 20, &pieces}); });
    setThreadBudget(0);
    const std::string whole = outcome([&] { return loadSceneString(*c.xml, path, {kWhole}); });
    EXPECT_EQ(fromFile.size(), whole.size());
    EXPECT_TRUE(fromFile == whole) << fromFile.substr(0, 200) << "\n" << whole.substr(0, 200);
    if (c.pieces > 0) EXPECT_GE(pieces, c.pieces);
    else EXPECT_EQ(pieces, 0u);
  }
  std::filesystem::remove(path);
}

// blind9: a mesh all of whose triangles have their corners on a line rendered as nothing,
// and its export did not parse (POV-Ray's Parse_Mesh: "No triangles in triangle mesh").
// One triangle of non-zero area keeps it; a lone degenerate triangle is still legal.
TEST(XmlLoader, AMeshOfOnlyDegenerateTrianglesIsRefusedAsPovRayRefusesIt) {
  EXPECT_SCENE_ERROR(inScene("<mesh>\n<triangle p1=\"1 1 1\" p2=\"1 1 1\" p3=\"1 1 1\"/>"
                             "<triangle p1=\"0 0 0\" p2=\"1 1 1\" p3=\"2 2 2\"/>\n</mesh>"),
                     "t.xml:2: error: mesh: every triangle of the mesh has its corners on a line, so it has none "
                     "(POV-Ray: \"No triangles in triangle mesh\")");
  EXPECT_NO_THROW(loadSceneString(inScene("<mesh><triangle p1=\"1 1 1\" p2=\"1 1 1\" p3=\"1 1 1\"/>"
                                          "<triangle p1=\"0 0 0\" p2=\"1 0 0\" p3=\"0 1 0\"/></mesh>"),
                                  "t.xml"));
  EXPECT_NO_THROW(loadSceneString(inScene("<triangle p1=\"1 1 1\" p2=\"1 1 1\" p3=\"1 1 1\"/>"), "t.xml"));
}

}  // namespace
}  // namespace pvrt
