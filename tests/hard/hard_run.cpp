#include "hard_run.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <vector>

#include <fmt/core.h>

#include "cases.h"
#include "oracle.h"
#include "scene/xml_loader.h"
#include "sweep.h"

namespace pvrt::hard {

namespace {


bool startsWith(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }


struct Outcome {
  bool pass = true;
  std::string figures;
  void add(const std::string& name, double value, bool ok = true) {
    figures += fmt::format(" {}={:.6g}", name, value);
    if (!ok) {
      pass = false;
      figures += "(FAIL)";
    }
  }
};

void addFigures(Outcome& out, const Figures& f) {
  out.add("compared", double(f.compared));
  if (f.skipped) out.add("skipped", double(f.skipped));
  out.add("errors", double(f.errors), f.errors == 0);
  out.add("edge_pixels", double(f.edge));
  out.add("edge_px", f.maxEdgePixels, f.maxEdgePixels <= 1.0);
  out.add("max_abs_err", f.maxAbsError);
  if (std::isfinite(f.closestPixels)) out.add("closest_px", f.closestPixels);
  if (f.lit) {
    out.add("lit", double(f.lit));
    out.add("acne_fraction", double(f.acne) / double(f.lit), f.acne == 0);
  }
}

// The exact answer of the case and its own extra checks.
void check(const std::string& name, const CaseInput& in, const RenderResult& r, const Scene& scene,
           const std::string& backend, double offset, Outcome& out) {
  const double absTol = 2e-6, relTol = 1e-5;
  auto compare = [&](const ExpectedImage& e) { addFigures(out, evaluate(e, r.image, absTol, relTol)); };
  if (startsWith(name, "tir_slab")) return compare(tirSlab(in));
  if (startsWith(name, "tir_sphere")) return compare(tirSphere(in));
  if (startsWith(name, "closed_mesh")) return compare(octahedron(in));
  if (startsWith(name, "degenerate_triangles")) return compare(unitSquare(in));
  if (startsWith(name, "mirrors")) {
    compare(facingMirrors(in));
    // Every camera ray bounces until the trace limit: N - 1 reflected rays each, the
    // analytic bound for any scene of perfect mirrors.
    const long pixels = long(in.width) * in.height;
    const long bound = pixels * (scene.globals.maxTraceLevel - 1);
    out.add("primary_rays", double(r.totals.primaryRays), long(r.totals.primaryRays) == pixels);
    out.add("reflected_rays", double(r.totals.reflectedRays), long(r.totals.reflectedRays) == bound);
    out.add("bound", double(bound));
    return;
  }
  if (startsWith(name, "coplanar")) {
    compare(coplanar(in));
    const DiscTies d = coplanarDisc(in, r.image);
    out.add("disc_pixels", double(d.pixels));
    out.add("disc_wins", double(d.disc));
    out.add("plane_wins", double(d.plane));
    out.add("neither", double(d.other), d.other == 0);
    return;
  }
  if (startsWith(name, "translate")) {
    // The same scene untranslated, on the same backend, must give the same image, except
    // where the image is not determined at the precision of the translated coordinates:
    // pixels that also change when the untranslated camera moves by a few units in the last
    // place of the offset (a ray grazing an edge seen through the glass ball, say).
    const std::string& b = backend;  // MPI: compared with serial renders
    const Image base = renderOn(buildScene(in.scene), in.width, in.height, b).image;
    const double ulp = std::nextafter(offset, INFINITY) - offset;
    std::vector<Image> nudged;
    for (const Vec3& dir : {Vec3(1, 1, 1), Vec3(-1, 1, -1), Vec3(1, -1, -1), Vec3(-1, -1, 1)}) {
      SceneDesc moved = in.scene;
      moved.camera.location += dir * (4 * ulp);
      if (moved.camera.lookAt) *moved.camera.lookAt += dir * (4 * ulp);
      nudged.push_back(renderOn(buildScene(moved), in.width, in.height, b).image);
    }
    const double level = 0.5 / 255;
    long differ = 0, unsettled = 0, unexplained = 0;
    for (size_t i = 0; i < base.data().size(); i += 3) {
      auto apart = [&](const Image& a, const Image& c) {
        for (size_t k = i; k < i + 3; ++k)
          if (std::fabs(a.data()[k] - c.data()[k]) > level) return true;
        return false;
      };
      bool loose = false;
      for (const Image& n : nudged) loose = loose || apart(base, n);
      unsettled += loose;
      if (apart(base, r.image)) {
        ++differ;
        if (!loose) ++unexplained;
      }
    }
    out.add("max_abs_diff", maxAbsDifference(base, r.image));
    out.add("pixels_over_half_level", double(differ));
    out.add("unsettled_pixels", double(unsettled));
    out.add("unexplained", double(unexplained), unexplained == 0);
    return;
  }
  compare(spheresAndPlanes(in));
}

}  // namespace

// The float image as a PFM file (no image library needed: the test starts faster).
void writePfm(const Image& image, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return;
  std::fprintf(f, "PF\n%d %d\n-1.0\n", image.width(), image.height());
  for (int y = image.height() - 1; y >= 0; --y) std::fwrite(image.row(y), sizeof(float), size_t(image.width()) * 3, f);
  std::fclose(f);
}

std::vector<std::string> caseNames() {
  std::vector<std::string> names;
  for (const auto& f : std::filesystem::directory_iterator(std::string(PVRT_SOURCE_DIR) + "/scenes/hard"))
    if (f.path().extension() == ".xml") names.push_back(f.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

std::vector<std::string> sweepsOf(const std::string& name) {
  if (startsWith(name, "translate")) return {"t1e3", "t1e5", "t1e7", "t1e8"};
  return {"0", "1", "2", "3"};
}

CaseResult runCase(const std::string& name, const std::string& sweepArg, const std::string& backend,
                   const RenderFn& renderWith, bool root, const std::string& dump) {
  Sweep sweep;
  if (sweepArg[0] == 't') sweep = {std::stod(sweepArg.substr(1)), 1};
  else sweep = kSweeps[std::stoi(sweepArg)];
  const SceneDesc canonical = loadSceneFile(std::string(PVRT_SOURCE_DIR) + "/scenes/hard/" + name + ".xml");
  const int w = canonical.image ? canonical.image->width : 64, h = canonical.image ? canonical.image->height : 48;
  const Scene scene = buildScene(applySweep(canonical, sweep));
  const RenderResult r = renderWith(scene, w, h);
  if (!root) return {};
  if (!dump.empty()) writePfm(r.image, dump);

  Outcome out;
  out.add("unit", scene.tol.unit);
  out.add("nonfinite", double(countNonFinite(r.image)), countNonFinite(r.image) == 0);
  // The renderer's own census: a NaN channel is written as 0, so the image alone
  // cannot show one.
  out.add("nonfinite_samples", double(r.totals.nonFiniteSamples), r.totals.nonFiniteSamples == 0);
  out.add("nonfinite_pixels", double(r.totals.nonFinitePixels), r.totals.nonFinitePixels == 0);
  if (backend != "serial") {
    const long d = countDifferent(renderOn(scene, w, h, "serial").image, r.image);
    out.add("differ_from_serial", double(d), d == 0);
  }
  const CaseInput in{canonical, scene.tol.shadow / sweep.scale, scene.tol.maxDistance / sweep.scale, w, h};
  check(name, in, r, scene, backend == "mpi" ? "serial" : backend, sweep.offset, out);
  return {out.pass, fmt::format("HARD {} {} {}: {} offset={:g} scale={:g}{}", name, sweepArg, backend,
                                out.pass ? "PASS" : "FAIL", sweep.offset, sweep.scale, out.figures)};
}

// Serial, or OpenMP with two threads: the renders the checks compare against.
RenderResult renderOn(const Scene& scene, int w, int h, const std::string& backend) {
  RenderSettings rs;
  rs.width = w;
  rs.height = h;
  rs.backend = backend == "openmp" ? Backend::OpenMP : Backend::Serial;
  rs.threads = backend == "openmp" ? 2 : 1;
  return render(scene, rs);
}

}  // namespace pvrt::hard
