#include "render/scene.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <optional>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/prefault.h"
#include "parallel/median.h"
#include "parallel/parallel_for.h"
#include "parallel/threads.h"

namespace pvrt {

RayTolerances rayTolerances(double typicalSize, const Vec3& camera) {
  RayTolerances t;
  t.typicalSize = typicalSize;
  t.unit = unitFor(typicalSize);
  t.minDepth = kMinIsectDepth * t.unit;
  t.shadow = kShadowTolerance * t.unit;
  t.maxDistance = std::max(kMaxDistance, kHorizonSizes * typicalSize);
  const Vec3 c = vabs(camera);
  t.primaryMinDepth = errorGamma(8) * std::max({c.x, c.y, c.z});
  return t;
}

namespace {

// The lower median of the bounded objects' sizes (0 when there are none): what the
// scene's objects are like, whatever one sky sphere or a speck of dust is like.
// `objects` holds each object's sizeOf() its box, or a negative number when it has none.
// Found on every thread, a block of objects each (`blocks`).
double typicalSize(const std::vector<double>& objects, const Blocks& blocks, int threads) {
  std::vector<std::vector<double>> sizes(blocks.count);
  std::vector<char> unordered(blocks.count, 0);  // a -0, which parallelNth cannot order
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i)
      if (objects[i] >= 0) {  // not NaN
        sizes[b].push_back(objects[i]);
        unordered[b] |= char(std::signbit(objects[i]));
      }
  });
  size_t n = 0;
  for (const std::vector<double>& part : sizes) n += part.size();
  if (n == 0) return 0;
  if (std::find(unordered.begin(), unordered.end(), 1) == unordered.end())
    return parallelNth<double>(sizes, (n - 1) / 2, threads);
  std::vector<double> all;
  for (const std::vector<double>& part : sizes) all.insert(all.end(), part.begin(), part.end());
  const auto mid = all.begin() + std::ptrdiff_t((n - 1) / 2);
  std::nth_element(all.begin(), mid, all.end());
  return *mid;
}

constexpr size_t kObjectsAtATime = 1024;  // the fewest objects of a block of the build

// The size a primitive's tolerances follow. A sphere or box kept in its own space (turned,
// or scaled unequally) is tested there, where the tolerances are lengths of that space, as
// POV-Ray's fixed ones are: its size as written, not the world's. The world's, for a sphere
// scaled <1e9, 0.3, 1> (2e9 across), made the unit 1e5 and the unit-sphere test's epsilons
// 1e-5 and 1 in a space where the sphere has radius 1: every ray missed it. Elsewhere the
// object's world size.
double localSize(const Primitive& p, double worldSize) {
  if (!p.transform) return worldSize;
  if (const auto* s = std::get_if<SphereShape>(&p.shape)) return 2 * s->radius;
  if (const auto* b = std::get_if<BoxShape>(&p.shape)) return sizeOf(Bounds{b->lo, b->hi});
  return worldSize;
}

// Uniform scale factor s when the linear part is s times a rotation, else 0.
double similarityScale(const Affine& a) {
  const double s2 = a.m[0][0] * a.m[0][0] + a.m[1][0] * a.m[1][0] + a.m[2][0] * a.m[2][0];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      double d = 0;
      for (int k = 0; k < 3; ++k) d += a.m[k][i] * a.m[k][j];
      const double want = i == j ? s2 : 0.0;
      if (std::fabs(d - want) > 1e-12 * s2) return 0.0;
    }
  return std::sqrt(s2);
}

// Where PrimitiveBuilder puts an object's primitives: at the end of `grow`; without it, it
// only counts them.
struct PrimitiveSink {
  std::vector<Primitive>* grow = nullptr;
  size_t made = 0;
};

class PrimitiveBuilder {
 public:
  PrimitiveBuilder(PrimitiveSink& out, uint32_t object, bool noShadow, const TransformList& steps)
      : out_(out), object_(object), noShadow_(noShadow), steps_(steps), xf_(steps.combined()),
        identity_(xf_.isIdentity()) {}

  void operator()(const SphereDesc& s) {
    const double k = similarityScale(xf_);
    if (k > 0) add(SphereShape{xf_.applyPoint(s.center), s.radius * k}, false);
    else add(SphereShape{s.center, s.radius}, true);
  }
  void operator()(const PlaneDesc& p) {
    const Vec3 n = unitDirection(p.normal);
    PlaneShape shape{n, p.distance};
    if (!identity_) {
      // Transform the plane itself: a point on it and its normal.
      const auto inv = xf_.inverse();
      const Vec3 point = xf_.applyPoint(n * p.distance);
      shape.normal = unitDirection(inv->applyTransposed(n));
      shape.distance = dot(shape.normal, point);
    }
    add(shape, false);
  }
  // A box as POV-Ray's parser makes it (Parse_Box, Box::Translate, Box::Scale,
  // Box::Transform): the corners sorted, each translate and scale before the first rotate or
  // matrix moving them one at a time, and from that rotate or matrix on every step composed
  // into the box's TRANSFORM, so that a turned box's faces tie with a plane as POV-Ray's do.
  void operator()(const BoxDesc& b) {
    Vec3 lo = vmin(b.corner1, b.corner2), hi = vmax(b.corner1, b.corner2);
    std::optional<PovTransform> trans;
    for (const TransformStep& step : steps_.steps) {
      if (!trans && step.kind == TransformStep::Kind::Translate) {
        lo = lo + step.v;
        hi = hi + step.v;
      } else if (!trans && step.kind == TransformStep::Kind::Scale) {
        const Vec3 a = mul(lo, step.v), c = mul(hi, step.v);
        lo = vmin(a, c);
        hi = vmax(a, c);
      } else {
        if (!trans) trans = PovTransform::identity();
        trans->then(povStep(step));
      }
    }
    if (add(BoxShape{lo, hi}, false) && trans) primitive().transform = share(trans->toTransform());
  }
  // Cylinders and cones in POV-Ray's canonical space, through its transform composed as its
  // parser composes it: their caps then tie with a plane as POV-Ray's do.
  void operator()(const CylinderDesc& c) { povCone(placeCylinder(c.base, c.cap, c.radius, c.open)); }
  void operator()(const ConeDesc& c) { povCone(placeCone(c.base, c.baseRadius, c.cap, c.capRadius, c.open)); }
  // Discs too: one lying on a plane ties with it as POV-Ray's does.
  void operator()(const DiscDesc& d) {
    PovDiscPlacement placed = placeDisc(d.center, d.normal, d.radius, d.holeRadius);
    for (const TransformStep& step : steps_.steps) placed.then(povStep(step));
    if (add(placed.shape, false)) primitive().transform = share(placed.transform.toTransform());
  }
  void operator()(const TriangleDesc& t) {
    PovTriangleBuilder b(t.p1, t.p2, t.p3);
    povSteps(b);
    PovTriangleShape shape = b.flat();
    if (b.degenerate()) shape.normal = Vec3{};  // never hit
    add(shape, false);
  }
  void operator()(const SmoothTriangleRef& t) {
    PovTriangleBuilder b(t->p1, t->n1, t->p2, t->n2, t->p3, t->n3);
    povSteps(b);
    // A lone smooth_triangle of zero area or whose vertex normals are not all strictly on one
    // side of its face is never hit ("Degenerate triangle": Compute_Triangle sets DEGENERATE_FLAG),
    // but Parse_Smooth_Triangle still returns it, with the box of its corners: it stays among the
    // objects, in the bounding threshold's count and in the tree, where its box moves the order
    // of ties between the others (blind14 b11). Kept as a flat triangle never hit, as a
    // degenerate lone triangle is.
    if (!b.degenerate()) {
      add(b.smooth(), false);
    } else {
      PovTriangleShape shape = b.flat();
      shape.normal = Vec3{};  // never hit
      add(shape, false);
    }
  }
  // A mesh as POV-Ray's parser makes it (Parse_Mesh, geometry/pov_mesh.h): its triangles in
  // mesh space, in the order the exporter writes them, and every transform written composed
  // into one TRANSFORM that they share. A mesh with no transform written has none (an
  // identity one written still carries each ray into mesh space and makes it unit again).
  void operator()(const MeshDesc& m) {
    SharedTransform trans;
    if (!steps_.steps.empty()) {
      PovTransform composed = PovTransform::identity();
      for (const TransformStep& step : steps_.steps) composed.then(povStep(step));
      trans = share(composed.toTransform());
    }
    PovMeshBuilder mesh;
    size_t made = 0;
    for (const auto& t : m.triangles)
      if (add(mesh.triangle(t.p1, t.p2, t.p3), false)) primitive().transform = trans, ++made;
    for (const auto& t : m.smoothTriangles) {
      bool smooth = false;
      PovMeshSmoothTriangleShape shape = mesh.smoothTriangle(t.p1, t.n1, t.p2, t.n2, t.p3, t.n3, smooth);
      if (smooth ? add(shape, false) : add(PovMeshTriangleShape(shape), false)) primitive().transform = trans, ++made;
    }
    if (made > 0) meshBox(made);
  }

 private:
  // The box POV-Ray keeps for a mesh, given to each of its `count` triangles (the last ones
  // made): Mesh::Compute_BBox, the range of its triangles' float corners (those its parser
  // kept), then Mesh::Transform's Recompute_BBox at each transform step in turn, not once
  // with the steps composed.
  void meshBox(size_t count) {
    std::vector<Primitive>& made = *out_.grow;
    constexpr double kBoundHuge = 2.0e10;  // POV-Ray's BOUND_HUGE
    Vec3 mins(kBoundHuge), maxs(-kBoundHuge);
    bool any = false;
    for (size_t k = made.size() - count; k < made.size(); ++k) {
      const auto* t = std::get_if<PovMeshTriangleShape>(&made[k].shape);
      if (!t) t = std::get_if<PovMeshSmoothTriangleShape>(&made[k].shape);
      if (!t || t->axis == PovMeshTriangleShape::kNever) continue;
      any = true;
      for (int i = 0; i < 3; ++i) mins = vmin(mins, t->corner(i)), maxs = vmax(maxs, t->corner(i));
    }
    if (!any) return;
    PovBBox box = povBBoxFromMinMax(mins, maxs);
    for (const TransformStep& step : steps_.steps) box = povRecomputed(box, povStep(step).toTransform().toWorld);
    for (size_t k = made.size() - count; k < made.size(); ++k) {
      made[k].povBox = box;
      made[k].povBoxKnown = true;
    }
  }
  void povCone(PovConePlacement placed) {
    for (const TransformStep& step : steps_.steps) placed.transform.then(povStep(step));
    if (add(placed.shape, false)) primitive().transform = share(placed.transform.toTransform());
  }
  // One transform written, as POV-Ray's parser makes it.
  static PovTransform povStep(const TransformStep& step) {
    switch (step.kind) {
      case TransformStep::Kind::Scale: return PovTransform::scaling(step.v);
      case TransformStep::Kind::Translate: return PovTransform::translation(step.v);
      case TransformStep::Kind::Rotate: return PovTransform::rotation(step.v);
      case TransformStep::Kind::Matrix: break;
    }
    return PovTransform::matrixOf(step.affine());  // the loader has refused singular matrices
  }
  // A lone triangle's transforms, one at a time as POV-Ray's parser applies them.
  void povSteps(PovTriangleBuilder& b) const {
    for (const TransformStep& step : steps_.steps) {
      switch (step.kind) {
        case TransformStep::Kind::Scale: b.scale(step.v); break;
        case TransformStep::Kind::Translate: b.translate(step.v); break;
        case TransformStep::Kind::Rotate:
        case TransformStep::Kind::Matrix: {
          const Transform t = povStep(step).toTransform();
          b.transform(t.toWorld, t.toObject);
          break;
        }
      }
    }
  }
  // False when only counting.
  bool add(Shape shape, bool keepTransform) {
    ++out_.made;
    if (!out_.grow) return false;
    Primitive p{std::move(shape), nullptr, object_, object_, noShadow_};
    if (keepTransform && !identity_) {
      if (!shared_) shared_ = share(Transform::from(xf_));  // one for all the object's primitives
      p.transform = shared_;
    }
    out_.grow->push_back(std::move(p));
    return true;
  }
  // The primitive add() made last.
  Primitive& primitive() { return out_.grow->back(); }

  PrimitiveSink& out_;
  uint32_t object_;
  bool noShadow_;
  const TransformList& steps_;
  Affine xf_;
  bool identity_;
  SharedTransform shared_;
};

// The primitives an object makes: one, but for a mesh's triangles.
size_t primitiveCount(const ObjectDesc& o) {
  if (const MeshDesc* mesh = std::get_if<MeshDesc>(&o.shape)) return mesh->triangles.size() + mesh->smoothTriangles.size();
  return 1;
}

EffectSet deriveEffects(const Scene& s, const SceneDesc& desc, int threads) {
  EffectSet e = 0;
  bool shadowCaster = false;
  for (const Light& l : s.lights) {
    if (!l.shadowless) shadowCaster = true;
    if (l.area && !l.shadowless) e |= kAreaLights;
    if (l.spot || (l.fadePower > 0 && l.fadeDistance != 0)) e |= kLightShaping;
  }
  if (shadowCaster && !desc.objects.empty()) e |= kShadows;
  // A material each object: a million of them, read on every thread.
  const Blocks blocks(s.materials.size(), threads, 4096);
  std::vector<EffectSet> found(blocks.count, 0);
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    EffectSet f = 0;
    for (size_t i = lo; i < hi; ++i) {
      const Material& m = s.materials[i];
      const Surface& surface = s.materials.surface(m);
      if (surface.reflective) f |= kReflection;
      if (!m.opaque) f |= kTransmission;
      if (surface.highlights && shadowCaster) f |= kHighlights;
      if (m.checker >= 0) f |= kTextures;
    }
    found[b] = f;
  });
  for (const EffectSet f : found) e |= f;
  return e;
}

// buildScene's body; `release`, when given, is desc.objects, freed once read.
Scene build(const SceneDesc& desc, std::vector<ObjectDesc>* release, const BuildOptions& options) {
  Scene s;
  s.camera = Camera(desc.camera);
  s.globals = desc.globals;
  s.background = desc.background;
  for (const LightDesc& l : desc.lights) s.lights.push_back(buildLight(l));

  const std::vector<ObjectDesc>& objects = desc.objects;
  const size_t objectCount = objects.size();  // before `release` takes them (the tie rule counts them)
  const int threads = threadBudget();
  s.materials.addObjects(objects, threads);
  interrupt::check();
  // The primitives, a block of objects at a time: each block's counted, then made where the
  // blocks before leave off. They go straight into their compact records (an untransformed
  // sphere is nothing more), so that a big scene never holds a Primitive for each.
  const Blocks blocks(objects.size(), threads, kObjectsAtATime);
  std::vector<size_t> first(blocks.count + 1, 0);
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    for (size_t i = lo; i < hi; ++i) first[b + 1] += primitiveCount(objects[i]);
  });
  interrupt::check();
  std::partial_sum(first.begin(), first.end(), first.begin());
  PrimitiveStore store;
  resizePrefaulted(store.records, first.back(), threads);
  std::vector<std::vector<Primitive>> others(blocks.count);      // each block's Kind::Other shapes
  std::vector<std::vector<uint32_t>> interiors(blocks.count);    // its primitives that hold the camera
  std::vector<double> objectSizes(objects.size(), -1);           // sizeOf() each object's box (a mesh is one)
  const Vec3 eye = s.camera.location();
  parallelBlocks(blocks, threads, [&](size_t b, size_t lo, size_t hi) {
    std::vector<Primitive> made;  // one object's
    PrimitiveSink sink{&made};
    size_t k = first[b];
    for (size_t i = lo; i < hi; ++i) {
      // A block may be a million objects on one thread: seconds (checked after the loop).
      if ((i & 4095) == 0 && interrupt::requested()) return;
      made.clear();
      std::visit(PrimitiveBuilder(sink, uint32_t(i), objects[i].noShadow, objects[i].transforms),
                 objects[i].shape);
      Bounds box;
      for (Primitive& p : made) {
        if (p.inside(eye)) interiors[b].push_back(p.object);
        p.opaque = s.materials[p.material].opaque;
        box.extend(p.bounds());
      }
      // Each shape's tolerances follow its own object's size (unbounded ones: the scene's
      // unit, set below), so that a sky sphere neither coarsens the others nor is lost to theirs.
      if (!box.empty()) objectSizes[i] = sizeOf(box);
      for (Primitive& p : made) {
        if (!box.empty()) p.unit = float(unitFor(localSize(p, objectSizes[i])));
        store.records[k++] = PrimitiveStore::compact(std::move(p), others[b]);
      }
    }
  });
  interrupt::check();
  for (size_t b = 0; b < blocks.count; ++b)
    for (uint32_t object : interiors[b])
      if (s.cameraInteriors.find(object) < 0) s.cameraInteriors.push(object);
  s.tol = rayTolerances(typicalSize(objectSizes, blocks, threads), eye);
  // The blocks' other shapes into one array, their records renumbered to match, and the
  // unbounded primitives given the scene's unit.
  std::vector<size_t> firstOther(blocks.count + 1, 0);
  for (size_t b = 0; b < blocks.count; ++b) firstOther[b + 1] = firstOther[b] + others[b].size();
  store.others.resize(firstOther.back());
  parallelBlocks(blocks, threads, [&](size_t b, size_t, size_t) {
    std::move(others[b].begin(), others[b].end(), store.others.begin() + std::ptrdiff_t(firstOther[b]));
    std::vector<Primitive>().swap(others[b]);
    for (size_t k = first[b]; k < first[b + 1]; ++k) {
      PrimitiveRecord& r = store.records[k];
      if (r.kind == PrimitiveRecord::Kind::Other) r.other += uint32_t(firstOther[b]);
      if (objectSizes[r.object] < 0) store.setUnit(k, float(s.tol.unit));
    }
  });
  s.effects = deriveEffects(s, desc, threads);
  if (release) std::vector<ObjectDesc>().swap(*release);
  interrupt::check();
  std::vector<double>().swap(objectSizes);
  s.bvh = Bvh(std::move(store));
  // Over the memory limit: the tree again with bigger leaves (far fewer nodes) until it fits
  // or the leaves are as big as they go; the primitives' own records are the floor.
  for (uint32_t leaf = 16; s.bvh.stats().bytes > options.memoryLimit && s.bvh.stats().leafSize < kBvhMaxLeafSize;
       leaf = std::min(4 * leaf, kBvhMaxLeafSize)) {
    s.bvh = Bvh(std::move(s.bvh).release(), 0, leaf);
    interrupt::check();
  }
  s.bvh.setTieRule(povTieRule(objectCount + desc.lights.size()));
  buildLightBuffers(s, options.memoryLimit, !options.memoryLimitGiven);
  interrupt::check();
  s.vista = Vista(s.camera, s.bvh);
  return s;
}

}  // namespace

Scene buildScene(const SceneDesc& desc, const BuildOptions& options) { return build(desc, nullptr, options); }
Scene buildScene(SceneDesc&& desc, const BuildOptions& options) { return build(desc, &desc.objects, options); }

// From how many bounded primitives a packet's shadow segments are answered from the light
// buffers one by one, rather than together (from one buffer cell when they all lie in one,
// else by one walk of the tree). 640x400, c=9, 2 threads, random spheres whose total volume
// is that of 100, render stage, alternating runs (2026-11-25): on 10^3 spheres together
// 0.34-0.48 s against 0.43-0.56 s one by one, on 3,000 0.56-0.59 s against 0.60-0.61 s
// (faster in 4 of 4), on 5,000 a tie (0.56-0.72 s against 0.62-0.69 s), on 10^4 one by one
// 0.60-0.77 s against 0.63-0.78 s, on 10^5 1.00-1.10 s against 1.39-1.65 s. (Before the
// cells, with the tree alone, the even point was 10^3.)
constexpr size_t kPacketShadowsFromBuffers = 4000;

void buildLightBuffers(Scene& s, size_t memoryLimit, bool scaled) {
  const auto start = std::chrono::steady_clock::now();
  s.lightBuffers.assign(s.lights.size(), LightBuffer{});
  s.memoryLimit = memoryLimit;
  s.memoryLimitScaled = false;
  s.lightsOverMemoryLimit = 0;
  if ((s.effects & kShadows) == 0) return;
  std::vector<size_t> which;
  for (size_t j = 0; j < s.lights.size(); ++j)
    if (!s.lights[j].area && !s.lights[j].shadowless) which.push_back(j);
  if (which.empty() || s.bvh.empty()) return;
  const std::vector<LightBuffer::Occluder> occluders = s.bvh.occluders();
  std::vector<Vec3> locations;
  for (size_t j : which) locations.push_back(s.lights[j].location);
  const size_t bvhBytes = s.bvh.stats().bytes + occluders.size() * sizeof(LightBuffer::Occluder);
  if (scaled && bvhBytes + lightBufferBudget(bvhBytes) < memoryLimit) {
    s.memoryLimit = memoryLimit = bvhBytes + lightBufferBudget(bvhBytes);
    s.memoryLimitScaled = true;
  }
  const size_t left = memoryLimit > bvhBytes ? memoryLimit - bvhBytes : 0;
  std::vector<LightBuffer> built = LightBuffer::build(locations, occluders, 0, left);
  for (size_t k = 0; k < which.size(); ++k) {
    s.lightsOverMemoryLimit += built[k].overMemoryLimit();
    s.lightBuffers[which[k]] = std::move(built[k]);
  }
  size_t bytes = 0;
  for (const LightBuffer& b : s.lightBuffers) bytes += b.bytes();
  s.prefetchLightBuffers = bytes > (size_t(16) << 20);
  s.packetShadowsFromBuffers = occluders.size() >= kPacketShadowsFromBuffers;
  s.lightBufferSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

std::string effectNames(EffectSet e) {
  static const char* names[] = {"shadows",   "reflection",    "transmission", "highlights",
                                "area-lights", "light-shaping", "textures",     "supersampling"};
  std::string out;
  for (int i = 0; i < 8; ++i)
    if (e & (1u << i)) out += (out.empty() ? "" : " ") + std::string(names[i]);
  return out.empty() ? "none" : out;
}

}  // namespace pvrt
