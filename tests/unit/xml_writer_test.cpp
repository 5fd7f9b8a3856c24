// The XML writer: what it writes loads back to an equal SceneDesc (numbers bit for bit),
// and writing that again gives the same text.
#include "scene/xml_writer.h"

#include <gtest/gtest.h>

#include <bit>
#include <cstdint>
#include <limits>
#include <string>

#include "generate/random_scene.h"
#include "scene/xml_attributes.h"
#include "scene/xml_loader.h"

namespace pvrt {
namespace {

// ---------------------------------------------------------------- exact comparison

// Doubles compare by their bits, so -0 differs from 0 and every last digit counts.
void same(double a, double b, const char* what) {
  EXPECT_EQ(std::bit_cast<uint64_t>(a), std::bit_cast<uint64_t>(b)) << what << ": " << a << " vs " << b;
}
void same(const Vec3& a, const Vec3& b, const char* what) {
  same(a.x, b.x, what);
  same(a.y, b.y, what);
  same(a.z, b.z, what);
}
void same(const Color& a, const Color& b, const char* what) {
  same(a.r, b.r, what);
  same(a.g, b.g, what);
  same(a.b, b.b, what);
}
void same(const FilterColor& a, const FilterColor& b, const char* what) {
  same(a.rgb, b.rgb, what);
  same(a.filter, b.filter, what);
  same(a.transmit, b.transmit, what);
}

void same(const TransformList& a, const TransformList& b, const char* what) {
  ASSERT_EQ(a.steps.size(), b.steps.size()) << what;
  for (size_t i = 0; i < a.steps.size(); ++i) {
    SCOPED_TRACE(testing::Message() << what << " step " << i);
    EXPECT_EQ(a.steps[i].kind, b.steps[i].kind);
    if (a.steps[i].kind == TransformStep::Kind::Matrix) {
      for (size_t k = 0; k < 12; ++k) same(a.steps[i].matrix[k], b.steps[i].matrix[k], "matrix");
    } else {
      same(a.steps[i].v, b.steps[i].v, "v");
    }
  }
}

void same(const MaterialDesc& a, const MaterialDesc& b) {
  EXPECT_EQ(a.name, b.name);
  const PigmentDesc &p = a.pigment, &q = b.pigment;
  ASSERT_EQ(p.checker != nullptr, q.checker != nullptr);
  if (p.checker) {
    same(p.checker->color1, q.checker->color1, "checker color1");
    same(p.checker->color2, q.checker->color2, "checker color2");
  } else {
    same(p.color, q.color, "pigment");
  }
  same(p.transforms, q.transforms, "pigment transforms");
  const FinishDesc &f = *a.finish, &g = *b.finish;
  same(f.ambient, g.ambient, "ambient");
  same(f.emission, g.emission, "emission");
  same(f.diffuse, g.diffuse, "diffuse");
  same(f.brilliance, g.brilliance, "brilliance");
  same(f.phong, g.phong, "phong");
  same(f.phongSize, g.phongSize, "phong_size");
  same(f.specular, g.specular, "specular");
  same(f.roughness, g.roughness, "roughness");
  same(f.metallic, g.metallic, "metallic");
  EXPECT_EQ(f.conserveEnergy, g.conserveEnergy);
  same(f.reflection.min, g.reflection.min, "reflection min");
  same(f.reflection.max, g.reflection.max, "reflection max");
  same(f.reflection.falloff, g.reflection.falloff, "reflection falloff");
  EXPECT_EQ(f.reflection.fresnel, g.reflection.fresnel);
  same(f.reflection.exponent, g.reflection.exponent, "reflection exponent");
  same(f.reflection.metallic, g.reflection.metallic, "reflection metallic");
  same(a.interior->ior, b.interior->ior, "ior");
  same(a.interior->fadeDistance, b.interior->fadeDistance, "interior fade_distance");
  same(a.interior->fadePower, b.interior->fadePower, "interior fade_power");
  same(a.interior->fadeColor, b.interior->fadeColor, "fade_color");
}

void same(const TriangleDesc& a, const TriangleDesc& b) {
  same(a.p1, b.p1, "p1");
  same(a.p2, b.p2, "p2");
  same(a.p3, b.p3, "p3");
}
void same(const SmoothTriangleDesc& a, const SmoothTriangleDesc& b) {
  same(a.p1, b.p1, "p1");
  same(a.n1, b.n1, "n1");
  same(a.p2, b.p2, "p2");
  same(a.n2, b.n2, "n2");
  same(a.p3, b.p3, "p3");
  same(a.n3, b.n3, "n3");
}

void same(const ShapeDesc& a, const ShapeDesc& b) {
  ASSERT_EQ(a.index(), b.index()) << shapeName(a) << " vs " << shapeName(b);
  if (const auto* s = std::get_if<SphereDesc>(&a)) {
    const auto& t = std::get<SphereDesc>(b);
    same(s->center, t.center, "center");
    same(s->radius, t.radius, "radius");
  } else if (const auto* s = std::get_if<PlaneDesc>(&a)) {
    const auto& t = std::get<PlaneDesc>(b);
    same(s->normal, t.normal, "normal");
    same(s->distance, t.distance, "distance");
  } else if (const auto* s = std::get_if<BoxDesc>(&a)) {
    const auto& t = std::get<BoxDesc>(b);
    same(s->corner1, t.corner1, "corner1");
    same(s->corner2, t.corner2, "corner2");
  } else if (const auto* s = std::get_if<CylinderDesc>(&a)) {
    const auto& t = std::get<CylinderDesc>(b);
    same(s->base, t.base, "base");
    same(s->cap, t.cap, "cap");
    same(s->radius, t.radius, "radius");
    EXPECT_EQ(s->open, t.open);
  } else if (const auto* s = std::get_if<ConeDesc>(&a)) {
    const auto& t = std::get<ConeDesc>(b);
    same(s->base, t.base, "base");
    same(s->baseRadius, t.baseRadius, "base_radius");
    same(s->cap, t.cap, "cap");
    same(s->capRadius, t.capRadius, "cap_radius");
    EXPECT_EQ(s->open, t.open);
  } else if (const auto* s = std::get_if<DiscDesc>(&a)) {
    const auto& t = std::get<DiscDesc>(b);
    same(s->center, t.center, "center");
    same(s->normal, t.normal, "normal");
    same(s->radius, t.radius, "radius");
    same(s->holeRadius, t.holeRadius, "hole_radius");
  } else if (const auto* s = std::get_if<TriangleDesc>(&a)) {
    same(*s, std::get<TriangleDesc>(b));
  } else if (const auto* s = std::get_if<SmoothTriangleRef>(&a)) {
    same(**s, *std::get<SmoothTriangleRef>(b));
  } else {
    const auto& m = std::get<MeshDesc>(a);
    const auto& n = std::get<MeshDesc>(b);
    ASSERT_EQ(m.triangles.size(), n.triangles.size());
    ASSERT_EQ(m.smoothTriangles.size(), n.smoothTriangles.size());
    for (size_t i = 0; i < m.triangles.size(); ++i) same(m.triangles[i], n.triangles[i]);
    for (size_t i = 0; i < m.smoothTriangles.size(); ++i) same(m.smoothTriangles[i], n.smoothTriangles[i]);
  }
}

// Every field but the source locations and the path.
void same(const SceneDesc& a, const SceneDesc& b) {
  const CameraDesc &c = a.camera, &d = b.camera;
  same(c.location, d.location, "camera location");
  same(c.direction, d.direction, "camera direction");
  same(c.up, d.up, "camera up");
  same(c.right, d.right, "camera right");
  same(c.sky, d.sky, "camera sky");
  ASSERT_EQ(c.lookAt.has_value(), d.lookAt.has_value());
  if (c.lookAt) same(*c.lookAt, *d.lookAt, "look_at");
  ASSERT_EQ(c.angle.has_value(), d.angle.has_value());
  if (c.angle) same(*c.angle, *d.angle, "angle");
  same(c.transforms, d.transforms, "camera transforms");

  EXPECT_EQ(a.globals.maxTraceLevel, b.globals.maxTraceLevel);
  same(a.globals.adcBailout, b.globals.adcBailout, "adc_bailout");
  same(a.globals.ambientLight, b.globals.ambientLight, "ambient_light");
  same(a.background, b.background, "background");
  ASSERT_EQ(a.image.has_value(), b.image.has_value());
  if (a.image) {
    EXPECT_EQ(a.image->width, b.image->width);
    EXPECT_EQ(a.image->height, b.image->height);
  }

  ASSERT_EQ(a.lights.size(), b.lights.size());
  for (size_t i = 0; i < a.lights.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "light " << i);
    const LightDesc &l = a.lights[i], &m = b.lights[i];
    same(l.location, m.location, "location");
    same(l.color, m.color, "color");
    same(l.fadeDistance, m.fadeDistance, "fade_distance");
    same(l.fadePower, m.fadePower, "fade_power");
    EXPECT_EQ(l.shadowless, m.shadowless);
    ASSERT_EQ(l.spot.has_value(), m.spot.has_value());
    if (l.spot) {
      same(l.spot->pointAt, m.spot->pointAt, "point_at");
      same(l.spot->radius, m.spot->radius, "spot radius");
      same(l.spot->falloff, m.spot->falloff, "spot falloff");
      same(l.spot->tightness, m.spot->tightness, "tightness");
    }
    ASSERT_EQ(l.area.has_value(), m.area.has_value());
    if (l.area) {
      same(l.area->axis1, m.area->axis1, "axis1");
      same(l.area->axis2, m.area->axis2, "axis2");
      EXPECT_EQ(l.area->size1, m.area->size1);
      EXPECT_EQ(l.area->size2, m.area->size2);
      EXPECT_EQ(l.area->adaptive, m.area->adaptive);
      EXPECT_EQ(l.area->circular, m.area->circular);
      EXPECT_EQ(l.area->orient, m.area->orient);
    }
  }

  ASSERT_EQ(a.materials.size(), b.materials.size());
  for (size_t i = 0; i < a.materials.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "material " << i);
    same(a.materials[i], b.materials[i]);
  }

  ASSERT_EQ(a.objects.size(), b.objects.size());
  for (size_t i = 0; i < a.objects.size(); ++i) {
    SCOPED_TRACE(testing::Message() << "object " << i << " (" << shapeName(a.objects[i].shape) << ")");
    const ObjectDesc &o = a.objects[i], &p = b.objects[i];
    same(o.shape, p.shape);
    EXPECT_EQ(o.namedMaterial, p.namedMaterial);
    same(o.material, p.material);
    same(o.transforms, p.transforms, "object transforms");
    EXPECT_EQ(o.noShadow, p.noShadow);
  }
}

// Loads, writes, reloads and rewrites; checks both the text and the values agree.
SceneDesc roundTrip(const SceneDesc& first) {
  const std::string text1 = sceneToXml(first);
  SceneDesc second;
  try {
    second = loadSceneString(text1, "written.xml");
  } catch (const std::exception& e) {
    ADD_FAILURE() << "the written scene does not load: " << e.what() << "\n" << text1;
    return second;
  }
  {
    SCOPED_TRACE("first load vs reload");
    same(first, second);
  }
  EXPECT_EQ(sceneToXml(second), text1);
  return second;
}

// ---------------------------------------------------------------- tests

// Uses every element and attribute, each away from its default.
const char* const kEveryFeature = R"(<?xml version="1.0"?>
<scene>
  <image width="64" height="48"/>
  <global_settings max_trace_level="7" adc_bailout="0.1" ambient_light="0.3333333333333333 0.5 1e-300"/>
  <background color="0.1 0.2 0.3"/>
  <camera location="0.1 -0 1e-300" direction="0 0 1.5" up="0 1.25 0" right="-1.6 0 0" sky="0 1 0.1"
          look_at="0 1 2" angle="55.5">
    <rotate v="0 30 0"/>
    <translate v="0 0.5 0"/>
  </camera>
  <light_source location="1 2 3"/>
  <light_source location="-1 8 -3" color="0.7 0.8 0.9" fade_distance="5" fade_power="2" shadowless="true">
    <spotlight point_at="0 0 0" radius="12" falloff="24" tightness="3"/>
    <area_light axis1="1 0 0" axis2="0 0 1" size1="3" size2="4" adaptive="2" circular="true" orient="true"/>
  </light_source>
  <light_source location="0 5 0">
    <area_light axis1="2 0 0" axis2="0 2 0"/>
  </light_source>
  <material name="floor">
    <pigment>
      <checker color1="1 1 1" filter1="0.1" transmit1="0.2" color2="0.25 0.3 0.4" filter2="0.3" transmit2="0.4"/>
      <scale v="2"/>
      <rotate v="0 45 0"/>
      <matrix v="1 0 0 0 1 0 0.5 0 1 0 0 0"/>
    </pigment>
    <finish ambient="0.2 0.3 0.4" emission="0.01" diffuse="0.9" brilliance="2" phong="0.8" phong_size="90"
            specular="0.3" roughness="0.01" metallic="0.5" conserve_energy="true" reflection="0.1 0.2 0.3"/>
    <interior ior="1.5" fade_distance="3" fade_power="2" fade_color="0.5 0.6 0.7"/>
  </material>
  <material name="fancy_2">
    <pigment color="1 0.5 0.25" filter="0.75" transmit="0.125"/>
    <finish>
      <reflection min="0.1" max="0.9 0.8 0.7" falloff="2" fresnel="true" exponent="0.5" metallic="0.25"/>
    </finish>
  </material>
  <material name="bare"/>
  <plane normal="0 1 0" distance="-1" material="floor"/>
  <plane normal="1 1 0" distance="0.5"/>
  <sphere center="0.1 0.2 0.3" radius="0.3333333333333333" no_shadow="true">
    <pigment color="0.9 0.2 0.2"/>
    <finish phong="0.6" phong_size="60"/>
    <scale v="1 0.5 0.8"/>
    <rotate v="0 30 20"/>
    <translate v="3.2 0.9 0.5"/>
  </sphere>
  <box corner1="-1 -2 -3" corner2="1 2 3" material="fancy_2">
    <matrix v="1 0 0 0.5 1 0 0 0 1 1.2 0 -3.2"/>
  </box>
  <cylinder base="0 0 0" cap="0 2 0" radius="0.5"/>
  <cylinder base="0 0 0" cap="1 0 0" radius="1e-300" open="true" material="bare"/>
  <cone base="0 0 0" base_radius="0" cap="0 1 0" cap_radius="0.5" open="true"/>
  <cone base="0 0 0" cap="0 1 0"/>
  <disc center="1 2 3" radius="2"/>
  <disc center="0 0 0" normal="0 0 -1" radius="2" hole_radius="0.5">
    <interior ior="1.33"/>
  </disc>
  <triangle p1="0 0 0" p2="1 0 0" p3="0 1 0">
    <pigment color="0.5"/>
  </triangle>
  <smooth_triangle p1="0 0 0" n1="0 0 -1" p2="1 0 0" n2="0 0.5 -1" p3="0 1 0" n3="1 0 -1"/>
  <mesh no_shadow="true">
    <triangle p1="0 0 0" p2="1 0 0" p3="0 1 0"/>
    <smooth_triangle p1="0 0 1" n1="0 0 1" p2="1 0 1" n2="0 0 1" p3="0 1 1" n3="0 0 1"/>
    <triangle p1="0 0 2" p2="1 0 2" p3="0 1 2"/>
    <pigment color="0.5 0.5 0.5" transmit="0.5">
      <translate v="1 2 3"/>
    </pigment>
    <scale v="2"/>
  </mesh>
</scene>
)";

TEST(XmlWriter, EveryFeatureRoundTripsTextAndValues) {
  const SceneDesc first = loadSceneString(kEveryFeature, "every.xml");
  ASSERT_EQ(first.objects.size(), 13u);
  const SceneDesc second = roundTrip(first);
  // The reload really carries the features (not just equal defaults on both sides).
  ASSERT_EQ(second.objects.size(), 13u);
  EXPECT_EQ(second.objects[0].namedMaterial, 0);
  EXPECT_EQ(second.objects[3].namedMaterial, 1);
  EXPECT_EQ(second.objects[5].namedMaterial, 2);
  EXPECT_EQ(second.objects[3].material.name, "fancy_2");
  EXPECT_TRUE(second.objects[3].material.finish->reflection.fresnel);
  EXPECT_EQ(second.materials[0].pigment.transforms.steps.size(), 3u);
  EXPECT_EQ(std::get<MeshDesc>(second.objects[12].shape).triangles.size(), 2u);
  EXPECT_EQ(std::get<MeshDesc>(second.objects[12].shape).smoothTriangles.size(), 1u);
  ASSERT_TRUE(second.lights[1].spot);
  ASSERT_TRUE(second.lights[1].area);
  EXPECT_TRUE(second.lights[1].area->orient);
  EXPECT_EQ(second.globals.maxTraceLevel, 7);
}

TEST(XmlWriter, NumbersSurviveBitForBit) {
  SceneDesc s;
  const double third = 1.0 / 3.0;
  const double tiny = 1e-300;
  const double denormal = std::numeric_limits<double>::denorm_min();
  const double huge = kMaxSceneNumber;  // the largest the loader accepts
  s.camera.location = {0.1, third, tiny};
  s.camera.angle = 0.1 + 0.2;  // 0.30000000000000004
  s.globals.adcBailout = third;
  s.background = {0.1, third, tiny};
  LightDesc l;
  l.location = {-0.0, denormal, -huge};
  l.color = {2.0 / 3.0, 1e-7, 123456789.123456789};
  s.lights.push_back(l);
  ObjectDesc o;
  o.shape = SphereDesc{{third, -third, 9.999999999999999e14}, third};
  o.material.pigment.color = {{0.1, 0.7, 0.9999999999999999}, third, tiny};
  o.material.finish.edit([&](FinishDesc& v) { v.diffuse = 0.1 * 3; });
  TransformStep t{};
  t.kind = TransformStep::Kind::Translate;
  t.v = {0.1, third, -tiny};
  o.transforms.steps.push_back(t);
  TransformStep m{};
  m.kind = TransformStep::Kind::Matrix;
  m.matrix = {1, 0, 0, 0, 1, 0, 0, 0, 1, third, 0.1, 2.0 / 7.0};
  o.transforms.steps.push_back(m);
  s.objects.push_back(o);

  const std::string text = sceneToXml(s);
  const SceneDesc back = loadSceneString(text, "n.xml");
  same(s, back);
  const auto& sp = std::get<SphereDesc>(back.objects.at(0).shape);
  EXPECT_EQ(sp.radius, 1.0 / 3.0);
  EXPECT_EQ(back.lights.at(0).location.y, denormal);
  EXPECT_TRUE(std::signbit(back.lights.at(0).location.x));
  EXPECT_EQ(back.camera.location.z, 1e-300);
  EXPECT_EQ(sceneToXml(back), text);
}

TEST(XmlWriter, EmptySceneWritesOnlyTheCamera) {
  EXPECT_EQ(sceneToXml(loadSceneString("<scene/>")),
            "<?xml version=\"1.0\"?>\n<scene>\n  <camera location=\"0 0 0\"/>\n</scene>\n");
}

TEST(XmlWriter, WritesExactlyWhatDiffersFromTheDefaults) {
  const std::string xml = sceneToXml(loadSceneString(R"(<scene>
    <camera location="0 1 -5" look_at="0 1 0"/>
    <light_source location="1 2 3" color="0.5"/>
    <sphere center="0 0 0" radius="1"><finish phong="0.5" reflection="0.25"/></sphere>
    <plane><pigment color="1 0 0"><translate v="0 1 0"/></pigment></plane>
  </scene>)"));
  EXPECT_EQ(xml,
            "<?xml version=\"1.0\"?>\n"
            "<scene>\n"
            "  <camera location=\"0 1 -5\" look_at=\"0 1 0\"/>\n"
            "  <light_source location=\"1 2 3\" color=\"0.5 0.5 0.5\"/>\n"
            "  <sphere center=\"0 0 0\" radius=\"1\">\n"
            "    <pigment color=\"0 0 0\"/>\n"
            "    <finish phong=\"0.5\" reflection=\"0.25 0.25 0.25\"/>\n"
            "  </sphere>\n"
            "  <plane normal=\"0 1 0\" distance=\"0\">\n"
            "    <pigment color=\"1 0 0\">\n"
            "      <translate v=\"0 1 0\"/>\n"
            "    </pigment>\n"
            "  </plane>\n"
            "</scene>\n");
}

TEST(XmlWriter, NamedMaterialsAreReferencedNotInlined) {
  const std::string xml = sceneToXml(loadSceneString(R"(<scene>
    <material name="red"><pigment color="1 0 0"/></material>
    <sphere center="0 0 0" radius="1" material="red" no_shadow="true"><scale v="2"/></sphere>
  </scene>)"));
  EXPECT_EQ(xml,
            "<?xml version=\"1.0\"?>\n"
            "<scene>\n"
            "  <camera location=\"0 0 0\"/>\n"
            "  <material name=\"red\">\n"
            "    <pigment color=\"1 0 0\"/>\n"
            "  </material>\n"
            "  <sphere center=\"0 0 0\" radius=\"1\" material=\"red\" no_shadow=\"true\">\n"
            "    <scale v=\"2 2 2\"/>\n"
            "  </sphere>\n"
            "</scene>\n");
}

TEST(XmlWriter, ReflectionIsWrittenAsAnElementOnlyWhenItNeedsOne) {
  const SceneDesc s = loadSceneString(R"(<scene>
    <sphere center="0 0 0" radius="1"><finish><reflection min="0.5"/></finish></sphere>
    <sphere center="0 0 0" radius="1"><finish><reflection max="0.5"/></finish></sphere>
    <sphere center="0 0 0" radius="1"><finish><reflection fresnel="true"/></finish></sphere>
  </scene>)");
  const std::string xml = sceneToXml(s);
  EXPECT_NE(xml.find("<finish reflection=\"0.5 0.5 0.5\"/>"), std::string::npos) << xml;
  EXPECT_NE(xml.find("<reflection min=\"0 0 0\" max=\"0.5 0.5 0.5\" falloff=\"1\" fresnel=\"false\" exponent=\"1\" "
                     "metallic=\"0\"/>"),
            std::string::npos)
      << xml;
  EXPECT_NE(xml.find("<reflection min=\"0 0 0\" max=\"0 0 0\" falloff=\"1\" fresnel=\"true\" exponent=\"1\" "
                     "metallic=\"0\"/>"),
            std::string::npos)
      << xml;
  roundTrip(s);
}

TEST(XmlWriter, GeneratedSceneRoundTrips) {
  const SceneDesc generated = generateScene(GenerateOptions{});
  ASSERT_EQ(generated.objects.size(), 101u);  // the floor and 100 spheres
  ASSERT_EQ(generated.lights.size(), 5u);
  const std::string text = sceneToXml(generated);
  const SceneDesc back = loadSceneString(text, "generated.xml");
  {
    SCOPED_TRACE("generated vs reload");
    same(generated, back);
  }
  EXPECT_EQ(sceneToXml(back), text);
  ASSERT_TRUE(back.image);
  EXPECT_EQ(back.image->width, 1280);
  EXPECT_EQ(back.image->height, 800);
  EXPECT_TRUE(std::get<PlaneDesc>(back.objects[0].shape).normal == Vec3(0, 1, 0));
  EXPECT_TRUE(back.objects[0].material.pigment.checker);
}

TEST(XmlWriter, GeneratedScenesOfOtherOptionsRoundTrip) {
  for (const GenerateOptions& o : {paperScene2(), [] {
                                     GenerateOptions g;
                                     g.spheres = 40;
                                     g.lights = 1;
                                     g.seed = 12345;
                                     g.palette = {0, 0, 1, 1};
                                     return g;
                                   }()}) {
    const SceneDesc generated = generateScene(o);
    SCOPED_TRACE(testing::Message() << "seed " << o.seed);
    same(generated, roundTrip(generated));
  }
}

}  // namespace
}  // namespace pvrt
