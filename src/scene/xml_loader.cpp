// The XML front end: turns tinyxml2's element tree into a SceneDesc, checking every
// value as it goes. The renderer never sees XML.
#include "scene/xml_loader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <future>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "core/error.h"
#include "core/prefault.h"
#include "scene/xml_attributes.h"
#include "scene/xml_document.h"
#include "scene/xml_split.h"

namespace pvrt {

namespace {

using tinyxml2::XMLElement;

// Every attribute each element may carry (docs/scene-format.md). The readers below check
// the values; this table lets a misspelt name be refused before any value is read.
const std::vector<std::string_view>& knownAttributes(std::string_view element) {
  static const std::map<std::string_view, std::vector<std::string_view>> table = [] {
    const std::vector<std::string_view> object{"material", "no_shadow"};
    auto shape = [&](std::vector<std::string_view> own) {
      own.insert(own.end(), object.begin(), object.end());
      return own;
    };
    return std::map<std::string_view, std::vector<std::string_view>>{
        {"scene", {}},
        {"image", {"width", "height"}},
        {"global_settings", {"max_trace_level", "adc_bailout", "ambient_light"}},
        {"background", {"color"}},
        {"camera", {"location", "direction", "up", "right", "sky", "look_at", "angle"}},
        {"light_source", {"location", "color", "fade_distance", "fade_power", "shadowless"}},
        {"spotlight", {"point_at", "radius", "falloff", "tightness"}},
        {"area_light", {"axis1", "axis2", "size1", "size2", "adaptive", "circular", "orient"}},
        {"material", {"name"}},
        {"pigment", {"color", "filter", "transmit"}},
        {"checker", {"color1", "filter1", "transmit1", "color2", "filter2", "transmit2"}},
        {"finish", {"ambient", "emission", "diffuse", "brilliance", "phong", "phong_size", "specular", "roughness",
                    "metallic", "conserve_energy", "reflection"}},
        {"reflection", {"min", "max", "falloff", "fresnel", "exponent", "metallic"}},
        {"interior", {"ior", "fade_distance", "fade_power", "fade_color"}},
        {"sphere", shape({"center", "radius"})},
        {"plane", shape({"normal", "distance"})},
        {"box", shape({"corner1", "corner2"})},
        {"cylinder", shape({"base", "cap", "radius", "open"})},
        {"cone", shape({"base", "base_radius", "cap", "cap_radius", "open"})},
        {"disc", shape({"center", "normal", "radius", "hole_radius"})},
        {"triangle", shape({"p1", "p2", "p3"})},  // inside a mesh, done() refuses the object ones
        {"smooth_triangle", shape({"p1", "n1", "p2", "n2", "p3", "n3"})},
        {"mesh", object},
        {"scale", {"v"}},
        {"rotate", {"v"}},
        {"translate", {"v"}},
        {"matrix", {"v"}},
    };
  }();
  static const std::vector<std::string_view> none;
  const auto it = table.find(element);
  return it == table.end() ? none : it->second;
}

class Loader {
 public:
  explicit Loader(const std::string& file) : file_(file) {}

  // The whole file as one tree.
  SceneDesc load(const tinyxml2::XMLDocument& doc) {
    const XMLElement* root = begin(doc);
    // Room for every element up front: a scene of a million objects would otherwise be
    // moved about twenty times as the vector grows, each time into fresh memory.
    size_t elements = 0;
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) ++elements;
    scene_.objects.reserve(elements);
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) element(e);
    return std::move(scene_);
  }

  // The file a piece at a time (scene/xml_split.h): `skeleton` is the file with the root's
  // children blanked out (their lines kept), `pieces` hold them. While one piece is read
  // into the scene, the next is parsed on another thread; pieces are read in file order, so
  // the scene and its first error are those of load(). nullopt when a piece is not
  // well-formed XML: only the whole file's parse can then tell which error comes first.
  std::optional<SceneDesc> loadPieces(const tinyxml2::XMLDocument& skeleton, std::string_view bytes,
                                      const XmlSplit& split) {
    const size_t count = split.pieces.size();
    tinyxml2::XMLDocument docs[2];  // piece k goes to docs[k % 2]
    auto parse = [&](size_t k) {
      const XmlPiece& p = split.pieces[k];
      return docs[k % 2].Parse(bytes.data() + p.begin, p.end - p.begin) == tinyxml2::XML_SUCCESS;
    };
    std::future<bool> next;  // parsing the piece after the one being read
    size_t wellFormed = 0;   // pieces [0, wellFormed) parsed without error
    try {
      const XMLElement* root = begin(skeleton);
      if (root->FirstChildElement()) return std::nullopt;  // the skeleton's root should be empty
      scene_.objects.reserve(split.elements);
      // A million objects' descriptions are 0.7 GB of fresh memory: faulted in by the other
      // core while this one parses and reads.
      prefault_ = prefaultAsync(scene_.objects.data(), scene_.objects.capacity() * sizeof(ObjectDesc));
      if (!parse(0)) return std::nullopt;
      wellFormed = 1;
      for (size_t k = 0; k < count; ++k) {
        if (k + 1 < count) next = std::async(std::launch::async, parse, k + 1);
        lineOffset_ = split.pieces[k].firstLine - 1;
        for (const XMLElement* e = docs[k % 2].FirstChildElement(); e; e = e->NextSiblingElement()) element(e);
        if (k + 1 < count) {
          if (!next.get()) return std::nullopt;
          wellFormed = k + 2;
        }
      }
    } catch (const Error&) {
      // The whole file's parse refuses malformed XML anywhere before any element is read.
      if (next.valid()) next.wait();  // its document is about to be parsed into again
      for (size_t k = wellFormed; k < count; ++k)
        if (!parse(k)) return std::nullopt;
      throw;
    }
    lineOffset_ = 0;
    return std::move(scene_);
  }

 private:
  // The checks of the document and its root; the root.
  const XMLElement* begin(const tinyxml2::XMLDocument& doc) {
    const XMLElement* root = doc.RootElement();
    if (!root) throw sceneError({file_, 1}, "scene", "the file has no <scene> element");
    // tinyxml2 keeps whatever follows the root; XML allows only comments there.
    for (const tinyxml2::XMLNode* n = doc.FirstChild(); n; n = n->NextSibling()) {
      const SourceLoc at{file_, n->GetLineNum()};
      if (n->ToUnknown()) throw sceneError(at, "xml", "<!DOCTYPE> and other <!...> are not supported");
      if (n->ToDeclaration() && n != doc.FirstChild())
        throw sceneError(at, "xml", "the <?xml ...?> declaration may appear only once, first");
      if (n->ToElement() && n != root)
        throw sceneError(at, printable(n->Value()), "a second root element (only one <scene> is allowed)");
    }
    if (std::strcmp(root->Name(), "scene") != 0)
      throw sceneError(locOf(root), printable(root->Name()), "the root element must be <scene>");
    attrs(root).done();
    noText(root);
    scene_.path = file_.str();
    return root;
  }

  // One child of the root.
  void element(const XMLElement* e) {
    noText(e);
    const std::string name = e->Name();
    if (name == "camera") {
      once(e, haveCamera_);
      scene_.camera = camera(e);
    } else if (name == "global_settings") {
      once(e, haveGlobals_);
      scene_.globals = globals(e);
    } else if (name == "background") {
      once(e, haveBackground_);
      Attributes a = attrs(e);
      scene_.background = a.color("color", {0, 0, 0});
      a.done();
      noChildren(e);
    } else if (name == "image") {
      if (scene_.image) throw sceneError(locOf(e), name, "may appear only once");
      scene_.image = image(e);
    } else if (name == "light_source") {
      scene_.lights.push_back(light(e));
    } else if (name == "material") {
      scene_.materials.push_back(namedMaterial(e));
    } else {
      scene_.objects.push_back(object(e));
    }
  }

  SourceLoc locOf(const XMLElement* e) const { return {file_, e->GetLineNum() + lineOffset_}; }
  Error errorAt(const XMLElement* e, const std::string& what) const {
    return sceneError(locOf(e), printable(e->Name()), what);
  }
  Attributes attrs(const XMLElement* e) const {
    return Attributes(e, file_, knownAttributes(e->Name()), lineOffset_);
  }

  void once(const XMLElement* e, bool& seen) const {
    if (seen) throw errorAt(e, "may appear only once");
    seen = true;
  }
  // Character data is never meaningful in the format; it is almost always a typo. Nor are
  // <!...> declarations, which tinyxml2 keeps as unknown nodes.
  void noText(const XMLElement* e) const {
    for (const tinyxml2::XMLNode* n = e->FirstChild(); n; n = n->NextSibling())
      if (n->ToUnknown() || n->ToDeclaration()) {
        throw sceneError({file_, n->GetLineNum() + lineOffset_}, "xml",
                         "<!...> and <?...?> are not allowed inside elements");
      } else if (const auto* t = n->ToText()) {
        const std::string_view s = t->Value();
        const size_t from = s.find_first_not_of(" \t\r\n");
        if (from == std::string_view::npos) continue;
        const size_t to = s.find_last_not_of(" \t\r\n");
        throw errorAt(e, "unexpected text \"" + printable(s.substr(from, to + 1 - from), 20) + "\"");
      }
  }
  void noChildren(const XMLElement* e) const {
    noText(e);
    if (const XMLElement* c = e->FirstChildElement())
      throw errorAt(c, std::string("unexpected element inside <") + e->Name() + ">");
  }

  ImageDesc image(const XMLElement* e) {
    Attributes a = attrs(e);
    ImageDesc d;
    d.loc = a.loc();
    if (!a.has("width")) throw a.missing("width");
    if (!a.has("height")) throw a.missing("height");
    d.width = a.integer("width", 0, 1, 65536);
    d.height = a.integer("height", 0, 1, 65536);
    if (static_cast<long long>(d.width) * d.height > ImageDesc::kMaxPixels)
      throw a.error(std::to_string(d.width) + " x " + std::to_string(d.height) + " pixels is more than " +
                    std::to_string(ImageDesc::kMaxPixels));
    a.done();
    noChildren(e);
    return d;
  }

  GlobalSettings globals(const XMLElement* e) {
    Attributes a = attrs(e);
    GlobalSettings g;
    g.loc = a.loc();
    g.maxTraceLevel = a.integer("max_trace_level", g.maxTraceLevel, 1, 256);
    g.adcBailout = a.nonNegative("adc_bailout", g.adcBailout);
    g.ambientLight = a.color("ambient_light", g.ambientLight);
    a.done();
    noChildren(e);
    return g;
  }

  CameraDesc camera(const XMLElement* e) {
    Attributes a = attrs(e);
    CameraDesc c;
    c.loc = a.loc();
    c.location = a.vec("location", c.location);
    c.direction = a.nonZeroVec("direction", c.direction);
    c.up = a.nonZeroVec("up", c.up);
    c.right = a.nonZeroVec("right", c.right);
    c.sky = a.nonZeroVec("sky", c.sky);
    if (a.has("look_at")) {
      c.lookAt = a.vec("look_at");
      if (*c.lookAt == c.location) throw a.error("look_at must differ from location");
    }
    if (a.has("angle")) {
      c.angle = a.number("angle");
      if (!(*c.angle > 0 && *c.angle < 180)) throw a.error("attribute 'angle' must lie between 0 and 180 degrees");
      // The direction's length is |right| / (2 tan(angle/2)): below about 1e-150 degrees its
      // square overflows, rays turn to NaN and the render never ends.
      if (*c.angle < 1e-6)
        throw a.error("attribute 'angle' must be at least 1e-6 degrees, got " + printable(e->Attribute("angle")));
    }
    a.done();
    if (dot(cross(c.up, c.right), cross(c.up, c.right)) == 0)
      throw a.error("up and right must not be parallel");
    c.transforms = transformsOnly(e);
    return c;
  }

  LightDesc light(const XMLElement* e) {
    Attributes a = attrs(e);
    LightDesc l;
    l.loc = a.loc();
    l.location = a.vec("location");
    l.color = a.color("color", l.color);
    l.fadeDistance = a.nonNegative("fade_distance", 0);
    l.fadePower = a.nonNegative("fade_power", 0);
    l.shadowless = a.boolean("shadowless", false);
    a.done();
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string name = c->Name();
      if (name != "spotlight" && name != "area_light")
        throw errorAt(c, "unknown element inside <light_source> (expected spotlight or area_light)");
      Attributes b = attrs(c);
      if (name == "spotlight") {
        if (l.spot) throw errorAt(c, "may appear only once");
        SpotlightDesc s;
        s.pointAt = b.vec("point_at", s.pointAt);
        s.radius = b.number("radius", s.radius);
        s.falloff = b.number("falloff", s.falloff);
        s.tightness = b.nonNegative("tightness", s.tightness);
        if (s.radius < 0 || s.radius > 90 || s.falloff < 0 || s.falloff > 90)
          throw b.error("radius and falloff must lie between 0 and 90 degrees");
        if (s.pointAt == l.location) throw b.error("point_at must differ from the light's location");
        l.spot = s;
      } else if (name == "area_light") {
        if (l.area) throw errorAt(c, "may appear only once");
        AreaLightDesc d;
        d.axis1 = b.vec("axis1");
        d.axis2 = b.vec("axis2");
        d.size1 = b.integer("size1", 1, 1, 1024);
        d.size2 = b.integer("size2", 1, 1, 1024);
        d.adaptive = b.integer("adaptive", d.adaptive, 0, 100);
        d.circular = b.boolean("circular", false);
        d.orient = b.boolean("orient", false);
        if ((d.circular || d.orient) && (d.size1 < 2 || d.size2 < 2))
          throw b.error("a circular or oriented area light needs size1 and size2 of at least 2");
        l.area = d;
      }
      b.done();
      noChildren(c);
    }
    return l;
  }

  MaterialDesc namedMaterial(const XMLElement* e) {
    Attributes a = attrs(e);
    MaterialDesc m;
    m.loc = a.loc();
    m.name = a.text("name");
    if (m.name.empty() || m.name.find_first_not_of(
                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") !=
                              std::string::npos)
      throw a.error("material names use letters, digits and '_' only, got \"" + printable(m.name) + "\"");
    for (const MaterialDesc& other : scene_.materials)
      if (other.name == m.name)
        throw a.error("material '" + m.name + "' is already defined at line " + std::to_string(other.loc.line));
    a.done();
    noText(e);
    bool pig = false, fin = false, inte = false;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
      if (!materialPart(c, m, pig, fin, inte))
        throw errorAt(c, "unknown element inside <material> (expected pigment, finish or interior)");
    return m;
  }

  // Reads a pigment, finish or interior into `m`; false when `c` is none of them.
  bool materialPart(const XMLElement* c, MaterialDesc& m, bool& pig, bool& fin, bool& inte) {
    const std::string name = c->Name();
    if (name == "pigment") {
      once(c, pig);
      m.pigment = pigment(c);
    } else if (name == "finish") {
      once(c, fin);
      m.finish = finish(c);
    } else if (name == "interior") {
      once(c, inte);
      m.interior = interior(c);
    } else {
      return false;
    }
    return true;
  }

  FilterColor filterColor(Attributes& a, const char* color, const char* filter, const char* transmit,
                          FilterColor fallback) {
    FilterColor f = fallback;
    f.rgb = a.color(color, f.rgb);
    f.filter = a.number(filter, f.filter);
    f.transmit = a.number(transmit, f.transmit);
    return f;
  }

  PigmentDesc pigment(const XMLElement* e) {
    Attributes a = attrs(e);
    PigmentDesc p;
    p.loc = a.loc();
    p.color = filterColor(a, "color", "filter", "transmit", p.color);
    a.done();
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (transformStep(c, p.transforms)) continue;
      if (std::strcmp(c->Name(), "checker") != 0)
        throw errorAt(c, "unknown element inside <pigment> (expected checker or a transform)");
      if (p.checker) throw errorAt(c, "may appear only once");
      if (e->Attribute("color") || e->Attribute("filter") || e->Attribute("transmit"))
        throw errorAt(c, "a checker pigment takes its colours from <checker>, not from <pigment>");
      Attributes b = attrs(c);
      CheckerDesc k;
      k.color1 = filterColor(b, "color1", "filter1", "transmit1", k.color1);
      k.color2 = filterColor(b, "color2", "filter2", "transmit2", k.color2);
      b.done();
      noChildren(c);
      p.checker = k;
    }
    checkSingular(e, p.transforms);
    return p;
  }

  FinishDesc finish(const XMLElement* e) {
    Attributes a = attrs(e);
    FinishDesc f;
    f.loc = a.loc();
    f.ambient = a.color("ambient", f.ambient);
    f.emission = a.color("emission", f.emission);
    f.diffuse = a.number("diffuse", f.diffuse);
    // Exponents of a cosine: negative ones are infinite at grazing angles.
    f.brilliance = a.nonNegative("brilliance", f.brilliance);
    f.phong = a.number("phong", f.phong);
    f.phongSize = a.nonNegative("phong_size", f.phongSize);
    f.specular = a.number("specular", f.specular);
    f.roughness = a.positive("roughness", f.roughness);
    f.metallic = a.number("metallic", f.metallic);
    f.conserveEnergy = a.boolean("conserve_energy", false);
    const bool flat = a.has("reflection");
    if (flat) {
      const Color r = a.color("reflection", {});
      f.reflection.min = f.reflection.max = r;
    }
    a.done();
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::strcmp(c->Name(), "reflection") != 0)
        throw errorAt(c, "unknown element inside <finish> (expected reflection)");
      if (flat) throw errorAt(c, "give reflection either as an attribute or as an element, not both");
      Attributes b = attrs(c);
      ReflectionDesc& r = f.reflection;
      r.min = b.color("min", r.min);
      r.max = b.color("max", r.min);  // one value means the same at every angle
      r.falloff = b.positive("falloff", r.falloff);
      r.fresnel = b.boolean("fresnel", false);
      r.exponent = b.positive("exponent", r.exponent);
      r.metallic = b.number("metallic", r.metallic);
      b.done();
      noChildren(c);
    }
    return f;
  }

  InteriorDesc interior(const XMLElement* e) {
    Attributes a = attrs(e);
    InteriorDesc in;
    in.loc = a.loc();
    in.ior = a.positive("ior", in.ior);
    // Far beyond any material; at about 1e9 the refraction overflows to infinite pixels.
    if (in.ior > 1000) throw a.error("attribute 'ior' must be at most 1000, got " + printable(e->Attribute("ior")));
    in.fadeDistance = a.nonNegative("fade_distance", in.fadeDistance);
    in.fadePower = a.nonNegative("fade_power", in.fadePower);
    in.fadeColor = a.color("fade_color", in.fadeColor);
    a.done();
    noChildren(e);
    return in;
  }

  // A transform child; false when `c` is not a transform.
  bool transformStep(const XMLElement* c, TransformList& list) {
    const std::string name = c->Name();
    TransformStep s{};
    if (name == "scale") s.kind = TransformStep::Kind::Scale;
    else if (name == "rotate") s.kind = TransformStep::Kind::Rotate;
    else if (name == "translate") s.kind = TransformStep::Kind::Translate;
    else if (name == "matrix") s.kind = TransformStep::Kind::Matrix;
    else return false;
    Attributes a = attrs(c);
    s.loc = a.loc();
    if (s.kind == TransformStep::Kind::Matrix) {
      if (!a.has("v")) throw a.missing("v");
      const auto w = words(c->Attribute("v"));
      if (w.size() != 12) throw a.error("attribute 'v' must hold 12 numbers, got " + std::to_string(w.size()));
      for (size_t i = 0; i < 12; ++i) s.matrix[i] = a.parseNumber("v", w[i]);
      if (!s.affine().inverse()) throw a.error("the matrix is singular");
    } else {
      s.v = s.kind == TransformStep::Kind::Scale ? a.vecOrScalar("v") : a.vec("v");
      if (s.kind == TransformStep::Kind::Scale && (s.v.x == 0 || s.v.y == 0 || s.v.z == 0))
        throw a.error("a scale factor of zero flattens the object");
    }
    a.done();
    noChildren(c);
    list.steps.push_back(s);
    return true;
  }

  TransformList transformsOnly(const XMLElement* e) {
    TransformList list;
    noText(e);
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement())
      if (!transformStep(c, list))
        throw errorAt(c, std::string("unknown element inside <") + e->Name() + "> (expected a transform)");
    checkSingular(e, list);
    return list;
  }

  // The product must be invertible, and neither it nor its inverse may reach beyond
  // kMaxSceneNumber: each step is in range, but many of them could multiply to inf.
  void checkSingular(const XMLElement* e, const TransformList& list) const {
    if (list.empty()) return;
    const Affine m = list.combined();
    const auto inverse = m.inverse();
    if (!inverse) throw errorAt(e, "its transforms together are singular");
    auto bounded = [](const Affine& a) {
      bool ok = std::fabs(a.t.x) <= kMaxSceneNumber && std::fabs(a.t.y) <= kMaxSceneNumber &&
                std::fabs(a.t.z) <= kMaxSceneNumber;
      for (const auto& row : a.m)
        for (double v : row) ok = ok && std::fabs(v) <= kMaxSceneNumber;
      return ok;
    };
    if (!bounded(m) || !bounded(*inverse))
      throw errorAt(e, "its transforms together scale by more than 1e15 or less than 1e-15, or move by more than 1e15");
  }

  ObjectDesc object(const XMLElement* e) {
    const std::string name = e->Name();
    static const std::set<std::string> shapes{"sphere", "plane", "box", "cylinder", "cone", "disc",
                                              "triangle", "smooth_triangle", "mesh"};
    if (!shapes.count(name))
      throw errorAt(e, "unknown element (expected camera, light_source, material, an object, ...)");
    Attributes a = attrs(e);
    ObjectDesc o;
    o.loc = a.loc();
    if (name == "sphere") {
      SphereDesc s;
      s.center = a.vec("center");
      s.radius = a.positive("radius");
      o.shape = s;
    } else if (name == "plane") {
      PlaneDesc p;
      p.normal = a.nonZeroVec("normal", p.normal);
      p.distance = a.number("distance", 0);
      o.shape = p;
    } else if (name == "box") {
      o.shape = BoxDesc{a.vec("corner1"), a.vec("corner2")};
    } else if (name == "cylinder") {
      CylinderDesc c;
      c.base = a.vec("base");
      c.cap = a.vec("cap");
      c.radius = a.positive("radius");
      c.open = a.boolean("open", false);
      if (c.base == c.cap) throw a.error("base and cap must differ");
      o.shape = c;
    } else if (name == "cone") {
      ConeDesc c;
      c.base = a.vec("base");
      c.baseRadius = a.nonNegative("base_radius", c.baseRadius);
      c.cap = a.vec("cap");
      c.capRadius = a.nonNegative("cap_radius", c.capRadius);
      c.open = a.boolean("open", false);
      if (c.base == c.cap) throw a.error("base and cap must differ");
      if (c.baseRadius == 0 && c.capRadius == 0) throw a.error("base_radius and cap_radius cannot both be 0");
      o.shape = c;
    } else if (name == "disc") {
      DiscDesc d;
      d.center = a.vec("center");
      d.normal = a.nonZeroVec("normal", d.normal);
      d.radius = a.positive("radius");
      d.holeRadius = a.nonNegative("hole_radius", 0);
      if (d.holeRadius >= d.radius) throw a.error("hole_radius must be smaller than radius");
      o.shape = d;
    } else if (name == "triangle") {
      o.shape = triangle(a);
    } else if (name == "smooth_triangle") {
      o.shape = smoothTriangle(a);
    } else {
      o.shape = MeshDesc{};
    }
    if (a.has("material")) {
      const std::string ref = a.text("material");
      for (size_t i = 0; i < scene_.materials.size(); ++i)
        if (scene_.materials[i].name == ref) o.namedMaterial = int(i);
      if (o.namedMaterial < 0) throw a.error("no material named '" + printable(ref) + "' is defined before it");
      o.material = scene_.materials[size_t(o.namedMaterial)];
    }
    o.noShadow = a.boolean("no_shadow", false);
    a.done();
    noText(e);

    bool pig = false, fin = false, inte = false;
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      noText(c);
      if (transformStep(c, o.transforms)) continue;
      if (auto* mesh = std::get_if<MeshDesc>(&o.shape)) {
        if (std::strcmp(c->Name(), "triangle") == 0) {
          Attributes b = attrs(c);
          mesh->triangles.push_back(triangle(b));
          b.done();
          noChildren(c);
          continue;
        }
        if (std::strcmp(c->Name(), "smooth_triangle") == 0) {
          Attributes b = attrs(c);
          mesh->smoothTriangles.push_back(smoothTriangle(b));
          b.done();
          noChildren(c);
          continue;
        }
      }
      if (o.namedMaterial >= 0 && (std::strcmp(c->Name(), "pigment") == 0 ||
                                   std::strcmp(c->Name(), "finish") == 0 ||
                                   std::strcmp(c->Name(), "interior") == 0))
        throw errorAt(c, "the object already uses material '" + o.material.name + "'");
      if (!materialPart(c, o.material, pig, fin, inte))
        throw errorAt(c, "unknown element inside <" + name + ">");
    }
    if (const auto* mesh = std::get_if<MeshDesc>(&o.shape))
      if (mesh->triangles.empty() && mesh->smoothTriangles.empty())
        throw errorAt(e, "a mesh needs at least one triangle or smooth_triangle");
    checkSingular(e, o.transforms);
    return o;
  }

  TriangleDesc triangle(Attributes& a) {
    TriangleDesc t{a.vec("p1"), a.vec("p2"), a.vec("p3"), a.loc()};
    return t;
  }
  SmoothTriangleDesc smoothTriangle(Attributes& a) {
    SmoothTriangleDesc t;
    t.loc = a.loc();
    t.p1 = a.vec("p1");
    t.n1 = a.nonZeroVec("n1");
    t.p2 = a.vec("p2");
    t.n2 = a.nonZeroVec("n2");
    t.p3 = a.vec("p3");
    t.n3 = a.nonZeroVec("n3");
    return t;
  }

  FileName file_;
  SceneDesc scene_;
  // Faulting in scene_.objects' storage; declared after scene_, so destroyed (and waited
  // for) before it.
  std::future<void> prefault_;
  bool haveCamera_ = false, haveGlobals_ = false, haveBackground_ = false;
  int lineOffset_ = 0;  // added to tinyxml2's line numbers: nonzero while reading a piece
};

// The file with the root's children replaced by their newlines alone: its declaration,
// comments, root and what follows keep their lines.
std::string skeletonOf(std::string_view bytes, const XmlSplit& split) {
  std::string out(bytes.substr(0, split.bodyBegin));
  out.append(size_t(std::count(bytes.begin() + std::ptrdiff_t(split.bodyBegin),
                                bytes.begin() + std::ptrdiff_t(split.bodyEnd), '\n')),
             '\n');
  out.append(bytes.substr(split.bodyEnd));
  return out;
}

SceneDesc parse(std::string_view bytes, const std::string& name, const LoadOptions& options) {
  if (options.piecesRead) *options.piecesRead = 0;
  checkSceneText(bytes, name);
  if (bytes.size() > options.pieceBytes) {
    if (const std::optional<XmlSplit> split = splitXmlRoot(bytes, options.pieceBytes)) {
      tinyxml2::XMLDocument skeleton;
      const std::string text = skeletonOf(bytes, *split);
      if (skeleton.Parse(text.data(), text.size()) == tinyxml2::XML_SUCCESS) {
        if (std::optional<SceneDesc> s = Loader(name).loadPieces(skeleton, bytes, *split)) {
          if (options.piecesRead) *options.piecesRead = split->pieces.size();
          s->path = name;
          return std::move(*s);
        }
      }
    }
  }
  tinyxml2::XMLDocument doc;
  parseCheckedText(doc, bytes, name);
  SceneDesc s = Loader(name).load(doc);
  s.path = name;
  return s;
}

}  // namespace

SceneDesc loadSceneString(const std::string& xml, const std::string& name, const LoadOptions& options) {
  return parse(xml, name, options);
}

SceneDesc loadSceneFile(const std::string& path, const LoadOptions& options) {
  return parse(readSceneBytes(path), path, options);
}

}  // namespace pvrt
