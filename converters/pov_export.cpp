#include "pov_export.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

namespace pvrt {

namespace {

// Shortest text that reads back to the same double.
std::string num(double v) { return fmt::format("{}", v == 0 ? 0.0 : v); }
std::string vec(const Vec3& v) { return "<" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ">"; }
std::string rgb(const Color& c) { return "rgb <" + num(c.r) + ", " + num(c.g) + ", " + num(c.b) + ">"; }
std::string rgbft(const FilterColor& c) {
  return "rgbft <" + num(c.rgb.r) + ", " + num(c.rgb.g) + ", " + num(c.rgb.b) + ", " + num(c.filter) + ", " +
         num(c.transmit) + ">";
}

class Writer {
 public:
  explicit Writer(const SceneDesc& s) : s_(s) {}

  PovExport run() {
    // The file name only: the export must not depend on where the repository lies.
    out_ += "// Exported by pvrt from " + std::filesystem::path(s_.path).filename().string() + "\n";
    if (s_.image) out_ += fmt::format("// Render with: +W{} +H{}\n", s_.image->width, s_.image->height);
    out_ += "#version 3.7;\n";
    const GlobalSettings& g = s_.globals;
    out_ += "global_settings { assumed_gamma 1.0 max_trace_level " + std::to_string(g.maxTraceLevel) +
            " adc_bailout " + num(g.adcBailout) + " ambient_light " + rgb(g.ambientLight) + " }\n";
    out_ += "background { color " + rgb(s_.background) + " }\n";
    camera(s_.camera);
    for (const LightDesc& l : s_.lights) light(l);
    for (const MaterialDesc& m : s_.materials) {
      out_ += "#declare " + declName(m.name) + " = material {\n";
      materialBody(m, "  ");
      out_ += "}\n";
    }
    for (const ObjectDesc& o : s_.objects) object(o);
    return {std::move(out_), std::move(warnings_)};
  }

 private:
  static std::string declName(const std::string& name) { return "pvrt_" + name; }

  void transforms(const TransformList& list, const std::string& indent) {
    for (const TransformStep& t : list.steps) {
      switch (t.kind) {
        case TransformStep::Kind::Scale: out_ += indent + "scale " + vec(t.v) + "\n"; break;
        case TransformStep::Kind::Rotate: out_ += indent + "rotate " + vec(t.v) + "\n"; break;
        case TransformStep::Kind::Translate: out_ += indent + "translate " + vec(t.v) + "\n"; break;
        case TransformStep::Kind::Matrix: {
          std::string m;
          for (size_t i = 0; i < t.matrix.size(); ++i) m += (i ? ", " : "") + num(t.matrix[i]);
          out_ += indent + "matrix <" + m + ">\n";
          break;
        }
      }
    }
  }

  void camera(const CameraDesc& c) {
    // POV-Ray applies camera modifiers in a fixed order whatever the order written; all
    // vectors are written so that no default (such as right 1.33) is left implicit.
    out_ += "camera {\n  perspective\n  location " + vec(c.location) + "\n  direction " + vec(c.direction) +
            "\n  up " + vec(c.up) + "\n  right " + vec(c.right) + "\n  sky " + vec(c.sky) + "\n";
    if (c.angle) out_ += "  angle " + num(*c.angle) + "\n";
    if (c.lookAt) out_ += "  look_at " + vec(*c.lookAt) + "\n";
    transforms(c.transforms, "  ");
    out_ += "}\n";
  }

  void light(const LightDesc& l) {
    out_ += "light_source {\n  " + vec(l.location) + "\n  color " + rgb(l.color) + "\n";
    if (l.spot)
      out_ += "  spotlight point_at " + vec(l.spot->pointAt) + " radius " + num(l.spot->radius) + " falloff " +
              num(l.spot->falloff) + " tightness " + num(l.spot->tightness) + "\n";
    if (l.area) {
      const AreaLightDesc& a = *l.area;
      out_ += "  area_light " + vec(a.axis1) + ", " + vec(a.axis2) + ", " + std::to_string(a.size1) + ", " +
              std::to_string(a.size2) + " adaptive " + std::to_string(a.adaptive) +
              // POV-Ray makes an oriented light circular itself, with a warning; written out, no warning.
              (a.circular || a.orient ? " circular" : "") + (a.orient ? " orient" : "") + "\n";
    }
    if (l.fadeDistance != 0 || l.fadePower != 0)
      out_ += "  fade_distance " + num(l.fadeDistance) + " fade_power " + num(l.fadePower) + "\n";
    if (l.shadowless) out_ += "  shadowless\n";
    out_ += "}\n";
  }

  void pigment(const PigmentDesc& p, const std::string& indent) {
    if (p.checker) {
      out_ += indent + "pigment { checker color " + rgbft(p.checker->color1) + ", color " +
              rgbft(p.checker->color2) + "\n";
      transforms(p.transforms, indent + "  ");
      out_ += indent + "}\n";
    } else {
      out_ += indent + "pigment { color " + rgbft(p.color) + " }\n";
    }
  }

  void finish(const FinishDesc& f, const std::string& indent) {
    out_ += indent + "finish {\n";
    const std::string in = indent + "  ";
    out_ += in + "ambient " + rgb(f.ambient) + " emission " + rgb(f.emission) + "\n";
    out_ += in + "diffuse " + num(f.diffuse) + " brilliance " + num(f.brilliance) + "\n";
    out_ += in + "phong " + num(f.phong) + " phong_size " + num(f.phongSize) + "\n";
    out_ += in + "specular " + num(f.specular) + " roughness " + num(f.roughness) + "\n";
    if (f.metallic != 0) out_ += in + "metallic " + num(f.metallic) + "\n";
    if (f.conserveEnergy) out_ += in + "conserve_energy\n";
    const ReflectionDesc& r = f.reflection;
    if (!r.isZero() || r.fresnel) {
      out_ += in + "reflection { " + rgb(r.min) + ", " + rgb(r.max) + " falloff " + num(r.falloff) + " exponent " +
              num(r.exponent);
      if (r.metallic != 0) out_ += " metallic " + num(r.metallic);
      if (r.fresnel) out_ += " fresnel on";
      out_ += " }\n";
    }
    out_ += indent + "}\n";
  }

  void interior(const InteriorDesc& i, const std::string& indent) {
    out_ += indent + "interior { ior " + num(i.ior);
    if (i.fadeDistance != 0)
      out_ += " fade_distance " + num(i.fadeDistance) + " fade_power " + num(i.fadePower) + " fade_color " +
              rgb(i.fadeColor);
    out_ += " }\n";
  }

  void materialBody(const MaterialDesc& m, const std::string& indent) {
    out_ += indent + "texture {\n";
    pigment(m.pigment, indent + "  ");
    finish(*m.finish, indent + "  ");
    out_ += indent + "}\n";
    interior(*m.interior, indent);
  }

  void triangle(const TriangleDesc& t, const std::string& indent) {
    out_ += indent + "triangle { " + vec(t.p1) + ", " + vec(t.p2) + ", " + vec(t.p3) + " }\n";
  }
  void smoothTriangle(const SmoothTriangleDesc& t, const std::string& indent) {
    out_ += indent + "smooth_triangle { " + vec(t.p1) + ", " + vec(t.n1) + ", " + vec(t.p2) + ", " + vec(t.n2) +
            ", " + vec(t.p3) + ", " + vec(t.n3) + " }\n";
  }

  // The shape keyword and its geometry, up to (not including) the closing brace.
  void shapeOpen(const ShapeDesc& shape) {
    struct Visitor {
      Writer& w;
      void operator()(const SphereDesc& s) { w.out_ += "sphere { " + vec(s.center) + ", " + num(s.radius) + "\n"; }
      void operator()(const PlaneDesc& p) { w.out_ += "plane { " + vec(p.normal) + ", " + num(p.distance) + "\n"; }
      void operator()(const BoxDesc& b) { w.out_ += "box { " + vec(b.corner1) + ", " + vec(b.corner2) + "\n"; }
      void operator()(const CylinderDesc& c) {
        w.out_ += "cylinder { " + vec(c.base) + ", " + vec(c.cap) + ", " + num(c.radius) + (c.open ? " open" : "") + "\n";
      }
      void operator()(const ConeDesc& c) {
        w.out_ += "cone { " + vec(c.base) + ", " + num(c.baseRadius) + ", " + vec(c.cap) + ", " + num(c.capRadius) +
                  (c.open ? " open" : "") + "\n";
      }
      void operator()(const DiscDesc& d) {
        w.out_ += "disc { " + vec(d.center) + ", " + vec(d.normal) + ", " + num(d.radius);
        if (d.holeRadius != 0) w.out_ += ", " + num(d.holeRadius);
        w.out_ += "\n";
      }
      void operator()(const TriangleDesc& t) {
        w.out_ += "triangle { " + vec(t.p1) + ", " + vec(t.p2) + ", " + vec(t.p3) + "\n";
      }
      void operator()(const SmoothTriangleRef& r) {
        const SmoothTriangleDesc& t = *r;
        w.out_ += "smooth_triangle { " + vec(t.p1) + ", " + vec(t.n1) + ", " + vec(t.p2) + ", " + vec(t.n2) + ", " +
                  vec(t.p3) + ", " + vec(t.n3) + "\n";
      }
      void operator()(const MeshDesc& m) {
        w.out_ += "mesh {\n";
        for (const auto& t : m.triangles) w.triangle(t, "  ");
        for (const auto& t : m.smoothTriangles) w.smoothTriangle(t, "  ");
      }
    };
    std::visit(Visitor{*this}, shape);
  }

  void object(const ObjectDesc& o) {
    shapeOpen(o.shape);
    // The texture comes before the transforms so that it moves with the object, as
    // pvrt's builder applies pattern transforms and then the object's.
    if (o.namedMaterial >= 0) {
      out_ += "  material { " + declName(s_.materials[size_t(o.namedMaterial)].name) + " }\n";
    } else {
      materialBody(o.material, "  ");
    }
    transforms(o.transforms, "  ");
    if (o.noShadow) out_ += "  no_shadow\n";
    out_ += "}\n";
  }

  const SceneDesc& s_;
  std::string out_;
  std::vector<std::string> warnings_;
};

}  // namespace

PovExport exportPov(const SceneDesc& scene) { return Writer(scene).run(); }

std::string withRecipe(const std::string& sdl, const SceneDesc& scene, const PovRecipe& r) {
  const std::string pov = std::filesystem::path(r.povName).filename().string();
  const std::string png = std::filesystem::path(pov).replace_extension(".png").string();
  const int width = scene.image ? scene.image->width : 320, height = scene.image ? scene.image->height : 240;
  const std::string recipe =
      fmt::format("// Render as `pvrt render --sampler pov --spp {}` does: {}\n", std::max(1, r.aaDepth * r.aaDepth),
                  povCommandLine(pov, png, width, height, r.aaDepth)) +
      "// (+A0.0 +AM1 +Rn -J: the pixel's centre ray and an n x n grid, no jitter, pvrt's --spp n*n; -A: --spp 1)\n";
  // After the header's comment lines, before the first line of SDL.
  size_t at = 0;
  while (sdl.compare(at, 2, "//") == 0) {
    const size_t end = sdl.find('\n', at);
    if (end == std::string::npos) break;
    at = end + 1;
  }
  return sdl.substr(0, at) + recipe + sdl.substr(at);
}

std::string povCommandLine(const std::string& pov, const std::string& png, int width, int height, int aaDepth,
                           const AdaptiveSettings& aa) {
  std::string options = "-A";
  if (aaDepth > 0) {
    // POV-Ray reads the threshold as a float: the shortest text that reads back as it.
    const std::string t = aa.threshold == 0 ? "0.0" : fmt::format("{}", float(aa.threshold));
    options = fmt::format("+A{} +AM{} +R{} -J", t, aa.method, aaDepth);
    if (aa.blockSize != 32) options += fmt::format(" +BS{}", aa.blockSize);
  }
  return fmt::format("povray +I{} +O{} +W{} +H{} -D +FN {}", pov, png, width, height, options);
}

}  // namespace pvrt
