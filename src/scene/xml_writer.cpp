// Writes a SceneDesc as pvrt XML. Only values that differ from the defaults are written,
// and numbers use the shortest form that reads back to the same double, so a scene
// survives load -> write -> load unchanged.
#include "scene/xml_writer.h"

#include <fmt/core.h>

namespace pvrt {

namespace {

std::string num(double v) { return fmt::format("{}", v); }
std::string vec(const Vec3& v) { return fmt::format("{} {} {}", v.x, v.y, v.z); }
std::string col(const Color& c) { return fmt::format("{} {} {}", c.r, c.g, c.b); }

// Escapes the few characters XML reserves (names are restricted, paths are not written).
std::string escape(const std::string& s) {
  std::string out;
  for (char ch : s) {
    if (ch == '&') out += "&amp;";
    else if (ch == '<') out += "&lt;";
    else if (ch == '"') out += "&quot;";
    else out += ch;
  }
  return out;
}

class Writer {
 public:
  std::string write(const SceneDesc& s) {
    out_ += "<?xml version=\"1.0\"?>\n<scene>\n";
    if (s.image) line(1, fmt::format("<image width=\"{}\" height=\"{}\"/>", s.image->width, s.image->height));
    globals(s.globals);
    if (!(s.background == Color{})) line(1, "<background color=\"" + col(s.background) + "\"/>");
    camera(s.camera);
    for (const LightDesc& l : s.lights) light(l);
    for (const MaterialDesc& m : s.materials) {
      line(1, "<material name=\"" + escape(m.name) + "\">");
      materialBody(m, 2);
      line(1, "</material>");
    }
    for (const ObjectDesc& o : s.objects) object(s, o);
    out_ += "</scene>\n";
    return std::move(out_);
  }

 private:
  void line(int depth, const std::string& text) { out_ += std::string(size_t(depth) * 2, ' ') + text + "\n"; }

  // Emits <tag attrs/> or <tag attrs> children </tag>.
  void element(int depth, const std::string& tag, const std::string& attrs, const std::string& children) {
    if (children.empty()) return line(depth, "<" + tag + attrs + "/>");
    line(depth, "<" + tag + attrs + ">");
    out_ += children;
    line(depth, "</" + tag + ">");
  }

  std::string transforms(const TransformList& list, int depth) {
    std::string out;
    const std::string pad(size_t(depth) * 2, ' ');
    for (const TransformStep& t : list.steps) {
      switch (t.kind) {
        case TransformStep::Kind::Scale: out += pad + "<scale v=\"" + vec(t.v) + "\"/>\n"; break;
        case TransformStep::Kind::Rotate: out += pad + "<rotate v=\"" + vec(t.v) + "\"/>\n"; break;
        case TransformStep::Kind::Translate: out += pad + "<translate v=\"" + vec(t.v) + "\"/>\n"; break;
        case TransformStep::Kind::Matrix: {
          std::string v;
          for (double x : t.matrix) v += (v.empty() ? "" : " ") + num(x);
          out += pad + "<matrix v=\"" + v + "\"/>\n";
        }
      }
    }
    return out;
  }

  void globals(const GlobalSettings& g) {
    const GlobalSettings d;
    std::string a;
    if (g.maxTraceLevel != d.maxTraceLevel) a += fmt::format(" max_trace_level=\"{}\"", g.maxTraceLevel);
    if (g.adcBailout != d.adcBailout) a += " adc_bailout=\"" + num(g.adcBailout) + "\"";
    if (!(g.ambientLight == d.ambientLight)) a += " ambient_light=\"" + col(g.ambientLight) + "\"";
    if (!a.empty()) line(1, "<global_settings" + a + "/>");
  }

  void camera(const CameraDesc& c) {
    const CameraDesc d;
    std::string a = " location=\"" + vec(c.location) + "\"";
    if (!(c.direction == d.direction)) a += " direction=\"" + vec(c.direction) + "\"";
    if (!(c.up == d.up)) a += " up=\"" + vec(c.up) + "\"";
    if (!(c.right == d.right)) a += " right=\"" + vec(c.right) + "\"";
    if (!(c.sky == d.sky)) a += " sky=\"" + vec(c.sky) + "\"";
    if (c.lookAt) a += " look_at=\"" + vec(*c.lookAt) + "\"";
    if (c.angle) a += " angle=\"" + num(*c.angle) + "\"";
    element(1, "camera", a, transforms(c.transforms, 2));
  }

  void light(const LightDesc& l) {
    std::string a = " location=\"" + vec(l.location) + "\"";
    if (!(l.color == Color{1, 1, 1})) a += " color=\"" + col(l.color) + "\"";
    if (l.fadeDistance != 0) a += " fade_distance=\"" + num(l.fadeDistance) + "\"";
    if (l.fadePower != 0) a += " fade_power=\"" + num(l.fadePower) + "\"";
    if (l.shadowless) a += " shadowless=\"true\"";
    std::string children;
    if (l.spot) {
      const SpotlightDesc& s = *l.spot;
      children += fmt::format("    <spotlight point_at=\"{}\" radius=\"{}\" falloff=\"{}\" tightness=\"{}\"/>\n",
                              vec(s.pointAt), s.radius, s.falloff, s.tightness);
    }
    if (l.area) {
      const AreaLightDesc& r = *l.area;
      children += fmt::format(
          "    <area_light axis1=\"{}\" axis2=\"{}\" size1=\"{}\" size2=\"{}\" adaptive=\"{}\" circular=\"{}\" "
          "orient=\"{}\"/>\n",
          vec(r.axis1), vec(r.axis2), r.size1, r.size2, r.adaptive, r.circular, r.orient);
    }
    element(1, "light_source", a, children);
  }

  static std::string filterAttrs(const FilterColor& f, const FilterColor& d, const std::string& suffix,
                                 const char* colorName) {
    std::string a;
    if (!(f.rgb == d.rgb)) a += " " + std::string(colorName) + "=\"" + col(f.rgb) + "\"";
    if (f.filter != d.filter) a += " filter" + suffix + "=\"" + num(f.filter) + "\"";
    if (f.transmit != d.transmit) a += " transmit" + suffix + "=\"" + num(f.transmit) + "\"";
    return a;
  }

  void materialBody(const MaterialDesc& m, int depth) {
    const MaterialDesc d;
    const PigmentDesc& p = m.pigment;
    std::string children = transforms(p.transforms, depth + 1);
    std::string attrs;
    if (p.checker) {
      const CheckerDesc dc;
      const std::string c = "<checker" + filterAttrs(p.checker->color1, dc.color1, "1", "color1") +
                            filterAttrs(p.checker->color2, dc.color2, "2", "color2") + "/>";
      children = std::string(size_t(depth + 1) * 2, ' ') + c + "\n" + children;
    } else {
      attrs = filterAttrs(p.color, FilterColor{}, "", "color");
      if (attrs.empty()) attrs = " color=\"0 0 0\"";  // always write the pigment: it is the common case
    }
    element(depth, "pigment", attrs, children);
    finish(*m.finish, depth);
    const InteriorDesc& in = *m.interior;
    std::string ia;
    if (in.ior != d.interior->ior) ia += " ior=\"" + num(in.ior) + "\"";
    if (in.fadeDistance != 0) ia += " fade_distance=\"" + num(in.fadeDistance) + "\"";
    if (in.fadePower != 0) ia += " fade_power=\"" + num(in.fadePower) + "\"";
    if (!(in.fadeColor == d.interior->fadeColor)) ia += " fade_color=\"" + col(in.fadeColor) + "\"";
    if (!ia.empty()) line(depth, "<interior" + ia + "/>");
  }

  void finish(const FinishDesc& f, int depth) {
    const FinishDesc d;
    std::string a;
    if (!(f.ambient == d.ambient)) a += " ambient=\"" + col(f.ambient) + "\"";
    if (!(f.emission == d.emission)) a += " emission=\"" + col(f.emission) + "\"";
    if (f.diffuse != d.diffuse) a += " diffuse=\"" + num(f.diffuse) + "\"";
    if (f.brilliance != d.brilliance) a += " brilliance=\"" + num(f.brilliance) + "\"";
    if (f.phong != d.phong) a += " phong=\"" + num(f.phong) + "\"";
    if (f.phongSize != d.phongSize) a += " phong_size=\"" + num(f.phongSize) + "\"";
    if (f.specular != d.specular) a += " specular=\"" + num(f.specular) + "\"";
    if (f.roughness != d.roughness) a += " roughness=\"" + num(f.roughness) + "\"";
    if (f.metallic != d.metallic) a += " metallic=\"" + num(f.metallic) + "\"";
    if (f.conserveEnergy) a += " conserve_energy=\"true\"";
    const ReflectionDesc& r = f.reflection;
    const ReflectionDesc dr;
    const bool simple = r.min == r.max && r.falloff == dr.falloff && r.fresnel == dr.fresnel &&
                        r.exponent == dr.exponent && r.metallic == dr.metallic;
    std::string children;
    if (simple && !r.isZero()) {
      a += " reflection=\"" + col(r.min) + "\"";
    } else if (!simple) {
      children = fmt::format("{}<reflection min=\"{}\" max=\"{}\" falloff=\"{}\" fresnel=\"{}\" exponent=\"{}\" "
                             "metallic=\"{}\"/>\n",
                             std::string(size_t(depth + 1) * 2, ' '), col(r.min), col(r.max), r.falloff, r.fresnel,
                             r.exponent, r.metallic);
    }
    if (!a.empty() || !children.empty()) element(depth, "finish", a, children);
  }

  void object(const SceneDesc& s, const ObjectDesc& o) {
    std::string a;
    struct Shape {
      std::string& a;
      std::string& body;
      void operator()(const SphereDesc& d) { a += " center=\"" + vec(d.center) + "\" radius=\"" + num(d.radius) + "\""; }
      void operator()(const PlaneDesc& d) { a += " normal=\"" + vec(d.normal) + "\" distance=\"" + num(d.distance) + "\""; }
      void operator()(const BoxDesc& d) { a += " corner1=\"" + vec(d.corner1) + "\" corner2=\"" + vec(d.corner2) + "\""; }
      void operator()(const CylinderDesc& d) {
        a += " base=\"" + vec(d.base) + "\" cap=\"" + vec(d.cap) + "\" radius=\"" + num(d.radius) + "\"";
        if (d.open) a += " open=\"true\"";
      }
      void operator()(const ConeDesc& d) {
        a += " base=\"" + vec(d.base) + "\" base_radius=\"" + num(d.baseRadius) + "\" cap=\"" + vec(d.cap) +
             "\" cap_radius=\"" + num(d.capRadius) + "\"";
        if (d.open) a += " open=\"true\"";
      }
      void operator()(const DiscDesc& d) {
        a += " center=\"" + vec(d.center) + "\" normal=\"" + vec(d.normal) + "\" radius=\"" + num(d.radius) + "\"";
        if (d.holeRadius != 0) a += " hole_radius=\"" + num(d.holeRadius) + "\"";
      }
      void operator()(const TriangleDesc& d) { a += tri(d); }
      void operator()(const SmoothTriangleRef& d) { a += smooth(*d); }
      void operator()(const MeshDesc& m) {
        for (const auto& t : m.triangles) body += "    <triangle" + tri(t) + "/>\n";
        for (const auto& t : m.smoothTriangles) body += "    <smooth_triangle" + smooth(t) + "/>\n";
      }
      static std::string tri(const TriangleDesc& d) {
        return " p1=\"" + vec(d.p1) + "\" p2=\"" + vec(d.p2) + "\" p3=\"" + vec(d.p3) + "\"";
      }
      static std::string smooth(const SmoothTriangleDesc& d) {
        return " p1=\"" + vec(d.p1) + "\" n1=\"" + vec(d.n1) + "\" p2=\"" + vec(d.p2) + "\" n2=\"" + vec(d.n2) +
               "\" p3=\"" + vec(d.p3) + "\" n3=\"" + vec(d.n3) + "\"";
      }
    };
    std::string body;
    std::visit(Shape{a, body}, o.shape);
    if (o.namedMaterial >= 0) a += " material=\"" + escape(s.materials[size_t(o.namedMaterial)].name) + "\"";
    if (o.noShadow) a += " no_shadow=\"true\"";
    if (o.namedMaterial < 0) {
      std::swap(out_, body);  // materialBody writes to out_; collect it into the body instead
      materialBody(o.material, 2);
      std::swap(out_, body);
    }
    body += transforms(o.transforms, 2);
    element(1, shapeName(o.shape), a, body);
  }

  std::string out_;
};

}  // namespace

std::string sceneToXml(const SceneDesc& scene) { return Writer().write(scene); }

}  // namespace pvrt
