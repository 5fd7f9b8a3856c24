// The XML front end: turns tinyxml2's element tree into a SceneDesc, checking every
// value as it goes. The renderer never sees XML.
#include "scene/xml_loader.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <fstream>
#include <set>
#include <sstream>
#include <string_view>
#include <sys/stat.h>

#include "core/error.h"

namespace pvrt {

namespace {

using tinyxml2::XMLElement;

// Splits "1 2 3" or "1, 2, 3" into its words.
std::vector<std::string> words(const char* text) {
  std::vector<std::string> out;
  std::string cur;
  for (const char* p = text; *p; ++p) {
    if (*p == ' ' || *p == ',' || *p == '\t' || *p == '\n' || *p == '\r') {
      if (!cur.empty()) out.push_back(std::move(cur));
      cur.clear();
    } else {
      cur += *p;
    }
  }
  if (!cur.empty()) out.push_back(std::move(cur));
  return out;
}

// For a number that std::from_chars read whole but found out of range: whether it is too
// large (rather than too small) for a double. Out-of-range magnitudes lie above 1e308 or
// below 1e-323, so the rough decimal exponent (digits before the point, less the zeros
// after it, plus the written exponent) tells them apart.
bool overflows(std::string_view w) {
  if (!w.empty() && w[0] == '-') w.remove_prefix(1);
  const size_t e = std::min(w.find_first_of("eE"), w.size());
  const std::string_view mantissa = w.substr(0, e);
  const size_t point = std::min(mantissa.find('.'), mantissa.size());
  const std::string_view whole = mantissa.substr(0, point);
  long long order = 0;
  if (const size_t nz = whole.find_first_not_of('0'); nz != std::string_view::npos) {
    order = static_cast<long long>(whole.size() - nz);
  } else if (point < mantissa.size()) {
    const std::string_view frac = mantissa.substr(point + 1);
    order = -static_cast<long long>(std::min(frac.find_first_not_of('0'), frac.size()));
  }
  if (e + 1 < w.size()) {
    std::string_view exp = w.substr(e + 1);
    const bool negative = exp[0] == '-';
    if (exp[0] == '-' || exp[0] == '+') exp.remove_prefix(1);
    long long x = 0;
    if (std::from_chars(exp.data(), exp.data() + exp.size(), x).ec != std::errc()) x = 1'000'000'000;
    order += negative ? -std::min(x, 1'000'000'000LL) : std::min(x, 1'000'000'000LL);
  }
  return order > 0;
}

// The attributes of one element. Each read marks its attribute as used, so that
// whatever is left over at the end is an unknown attribute and an error.
class Attributes {
 public:
  Attributes(const XMLElement* e, const std::string& file) : e_(e), file_(file) {}

  SourceLoc loc() const { return {file_, e_->GetLineNum()}; }
  Error error(const std::string& what) const { return sceneError(loc(), e_->Name(), what); }

  bool has(const char* name) { used_.insert(name); return e_->Attribute(name) != nullptr; }

  double number(const char* name, double fallback) { return has(name) ? number(name) : fallback; }
  double number(const char* name) {
    const auto w = wordsOf(name);
    if (w.size() != 1) throw error(attr(name) + " must be one number, got \"" + raw(name) + "\"");
    return parseNumber(name, w[0]);
  }
  // A non-negative number.
  double nonNegative(const char* name, double fallback) {
    const double v = number(name, fallback);
    if (v < 0) throw error(attr(name) + " must not be negative, got " + raw(name));
    return v;
  }
  double positive(const char* name, std::optional<double> fallback = std::nullopt) {
    if (!fallback && !has(name)) throw missing(name);
    const double v = number(name, fallback.value_or(0));
    if (!(v > 0)) throw error(attr(name) + " must be positive, got " + raw(name));
    return v;
  }
  double required(const char* name) {
    if (!has(name)) throw missing(name);
    return number(name);
  }

  int integer(const char* name, int fallback, int lo, int hi) {
    if (!has(name)) return fallback;
    const std::string text = raw(name);
    long long v = 0;
    const char* end = text.data() + text.size();
    auto [p, ec] = std::from_chars(text.data(), end, v);
    if (ec == std::errc::result_out_of_range || (ec == std::errc() && p == end && (v < lo || v > hi)))
      throw error(attr(name) + " must be an integer from " + std::to_string(lo) + " to " +
                  std::to_string(hi) + ", got " + text);
    if (ec != std::errc() || p != end) throw error(attr(name) + " must be an integer, got \"" + text + "\"");
    return int(v);
  }

  Vec3 vec(const char* name, Vec3 fallback) { return has(name) ? vec(name) : fallback; }
  Vec3 vec(const char* name) {
    if (!has(name)) throw missing(name);
    const auto w = wordsOf(name);
    if (w.size() != 3) throw error(attr(name) + " must be a vector of 3 numbers, got \"" + raw(name) + "\"");
    return {parseNumber(name, w[0]), parseNumber(name, w[1]), parseNumber(name, w[2])};
  }
  Vec3 nonZeroVec(const char* name, std::optional<Vec3> fallback = std::nullopt) {
    const Vec3 v = fallback ? vec(name, *fallback) : vec(name);
    if (dot(v, v) == 0) throw error(attr(name) + " must not be the zero vector");
    return v;
  }
  // "x y z", or one number for all three (scale 2 = scale <2,2,2>).
  Vec3 vecOrScalar(const char* name) {
    if (!has(name)) throw missing(name);
    const auto w = wordsOf(name);
    if (w.size() == 1) return Vec3(parseNumber(name, w[0]));
    return vec(name);
  }
  // Colours are "r g b", or one number for a grey.
  Color color(const char* name, Color fallback) {
    if (!has(name)) return fallback;
    const Vec3 v = vecOrScalar(name);
    return {v.x, v.y, v.z};
  }

  bool boolean(const char* name, bool fallback) {
    if (!has(name)) return fallback;
    const std::string v = raw(name);
    if (v == "true") return true;
    if (v == "false") return false;
    throw error(attr(name) + " must be true or false, got \"" + v + "\"");
  }

  std::string text(const char* name) {
    if (!has(name)) throw missing(name);
    return raw(name);
  }

  // Call after reading: any attribute not read is unknown.
  void done() const {
    for (const tinyxml2::XMLAttribute* a = e_->FirstAttribute(); a; a = a->Next())
      if (!used_.count(a->Name())) throw error("unknown attribute '" + std::string(a->Name()) + "'");
  }

  Error missing(const char* name) const { return error("missing required attribute '" + std::string(name) + "'"); }

  double parseNumber(const char* name, const std::string& w) const {
    double v = 0;
    const char* begin = w.data();
    if (*begin == '+') ++begin;
    const char* end = w.data() + w.size();
    auto [p, ec] = std::from_chars(begin, end, v);
    // from_chars leaves `v` untouched when out of range, so tell underflow (a number too
    // tiny for a double: zero) from overflow (an error) by its decimal exponent.
    if (ec == std::errc::result_out_of_range && p == end && !overflows(std::string_view(begin, end)))
      ec = std::errc();
    if (ec == std::errc::result_out_of_range)
      throw error(attr(name) + ": " + w + " is out of range");
    if (ec != std::errc() || p != end) throw error(attr(name) + ": \"" + w + "\" is not a number");
    if (!std::isfinite(v)) throw error(attr(name) + ": " + w + " is not a finite number");
    return v;
  }

 private:
  std::string raw(const char* name) const { return e_->Attribute(name); }
  static std::string attr(const char* name) { return "attribute '" + std::string(name) + "'"; }
  std::vector<std::string> wordsOf(const char* name) { return words(e_->Attribute(name)); }

  const XMLElement* e_;
  const std::string& file_;
  std::set<std::string> used_;
};

class Loader {
 public:
  explicit Loader(std::string file) : file_(std::move(file)) {}

  SceneDesc load(const tinyxml2::XMLDocument& doc) {
    const XMLElement* root = doc.RootElement();
    if (!root) throw sceneError({file_, 1}, "scene", "the file has no <scene> element");
    if (std::strcmp(root->Name(), "scene") != 0)
      throw sceneError(locOf(root), root->Name(), "the root element must be <scene>");
    Attributes(root, file_).done();
    noText(root);
    scene_.path = file_;
    bool haveCamera = false, haveGlobals = false, haveBackground = false;
    for (const XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
      noText(e);
      const std::string name = e->Name();
      if (name == "camera") {
        once(e, haveCamera);
        scene_.camera = camera(e);
      } else if (name == "global_settings") {
        once(e, haveGlobals);
        scene_.globals = globals(e);
      } else if (name == "background") {
        once(e, haveBackground);
        Attributes a(e, file_);
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
    return std::move(scene_);
  }

 private:
  SourceLoc locOf(const XMLElement* e) const { return {file_, e->GetLineNum()}; }
  Error errorAt(const XMLElement* e, const std::string& what) const {
    return sceneError(locOf(e), e->Name(), what);
  }

  void once(const XMLElement* e, bool& seen) const {
    if (seen) throw errorAt(e, "may appear only once");
    seen = true;
  }
  // Character data is never meaningful in the format; it is almost always a typo.
  void noText(const XMLElement* e) const {
    for (const tinyxml2::XMLNode* n = e->FirstChild(); n; n = n->NextSibling())
      if (const auto* t = n->ToText()) {
        const std::string s = t->Value();
        if (s.find_first_not_of(" \t\r\n") != std::string::npos)
          throw errorAt(e, "unexpected text \"" + s.substr(s.find_first_not_of(" \t\r\n"), 20) + "\"");
      }
  }
  void noChildren(const XMLElement* e) const {
    noText(e);
    if (const XMLElement* c = e->FirstChildElement())
      throw sceneError(locOf(c), c->Name(), std::string("unexpected element inside <") + e->Name() + ">");
  }

  ImageDesc image(const XMLElement* e) {
    Attributes a(e, file_);
    ImageDesc d;
    d.loc = a.loc();
    if (!a.has("width")) throw a.missing("width");
    if (!a.has("height")) throw a.missing("height");
    d.width = a.integer("width", 0, 1, 65536);
    d.height = a.integer("height", 0, 1, 65536);
    a.done();
    noChildren(e);
    return d;
  }

  GlobalSettings globals(const XMLElement* e) {
    Attributes a(e, file_);
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
    Attributes a(e, file_);
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
    }
    a.done();
    if (dot(cross(c.up, c.right), cross(c.up, c.right)) == 0)
      throw a.error("up and right must not be parallel");
    c.transforms = transformsOnly(e);
    return c;
  }

  LightDesc light(const XMLElement* e) {
    Attributes a(e, file_);
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
      Attributes b(c, file_);
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
      } else {
        throw errorAt(c, "unknown element inside <light_source> (expected spotlight or area_light)");
      }
      b.done();
      noChildren(c);
    }
    return l;
  }

  MaterialDesc namedMaterial(const XMLElement* e) {
    Attributes a(e, file_);
    MaterialDesc m;
    m.loc = a.loc();
    m.name = a.text("name");
    if (m.name.empty() || m.name.find_first_not_of(
                              "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_") !=
                              std::string::npos)
      throw a.error("material names use letters, digits and '_' only, got \"" + m.name + "\"");
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
    Attributes a(e, file_);
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
      Attributes b(c, file_);
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
    Attributes a(e, file_);
    FinishDesc f;
    f.loc = a.loc();
    f.ambient = a.color("ambient", f.ambient);
    f.emission = a.color("emission", f.emission);
    f.diffuse = a.number("diffuse", f.diffuse);
    f.brilliance = a.number("brilliance", f.brilliance);
    f.phong = a.number("phong", f.phong);
    f.phongSize = a.number("phong_size", f.phongSize);
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
      Attributes b(c, file_);
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
    Attributes a(e, file_);
    InteriorDesc in;
    in.loc = a.loc();
    in.ior = a.positive("ior", in.ior);
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
    Attributes a(c, file_);
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

  void checkSingular(const XMLElement* e, const TransformList& list) const {
    if (!list.empty() && !list.combined().inverse())
      throw errorAt(e, "its transforms together are singular");
  }

  ObjectDesc object(const XMLElement* e) {
    const std::string name = e->Name();
    Attributes a(e, file_);
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
    } else if (name == "mesh") {
      o.shape = MeshDesc{};
    } else {
      throw errorAt(e, "unknown element (expected camera, light_source, material, an object, ...)");
    }
    if (a.has("material")) {
      const std::string ref = a.text("material");
      for (size_t i = 0; i < scene_.materials.size(); ++i)
        if (scene_.materials[i].name == ref) o.namedMaterial = int(i);
      if (o.namedMaterial < 0) throw a.error("no material named '" + ref + "' is defined before it");
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
        Attributes b(c, file_);
        if (std::strcmp(c->Name(), "triangle") == 0) {
          mesh->triangles.push_back(triangle(b));
          b.done();
          noChildren(c);
          continue;
        }
        if (std::strcmp(c->Name(), "smooth_triangle") == 0) {
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

  std::string file_;
  SceneDesc scene_;
};

SceneDesc parse(const std::string& xml, const std::string& name, const std::string& path) {
  tinyxml2::XMLDocument doc;
  if (doc.Parse(xml.data(), xml.size()) != tinyxml2::XML_SUCCESS) {
    const int line = std::max(1, doc.ErrorLineNum());
    std::string what = doc.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT ? "the file is empty"
                                                                         : "malformed XML";
    if (doc.ErrorID() != tinyxml2::XML_ERROR_EMPTY_DOCUMENT) what += std::string(" (") + doc.ErrorName() + ")";
    throw sceneError({name, line}, "xml", what);
  }
  SceneDesc s = Loader(name).load(doc);
  s.path = path;
  return s;
}

}  // namespace

SceneDesc loadSceneString(const std::string& xml, const std::string& name) { return parse(xml, name, name); }

SceneDesc loadSceneFile(const std::string& path) {
  struct stat st {};
  if (stat(path.c_str(), &st) != 0)
    throw Error(ExitCode::SceneError, path + ": cannot read scene: " + std::strerror(errno));
  if (S_ISDIR(st.st_mode)) throw Error(ExitCode::SceneError, path + ": cannot read scene: it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error(ExitCode::SceneError, path + ": cannot read scene: " + std::strerror(errno));
  std::ostringstream text;
  text << in.rdbuf();
  if (in.bad()) throw Error(ExitCode::SceneError, path + ": cannot read scene: read error");
  return parse(text.str(), path, path);
}

}  // namespace pvrt
