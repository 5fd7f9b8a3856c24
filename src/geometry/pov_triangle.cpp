// POV-Ray 3.7's Triangle and SmoothTriangle (source/backend/shape/triangle.cpp): the same
// operations in the same order, since their rounding decides pixels. Vector operations
// follow POV-Ray's helpers: a vector is made unit by multiplying with 1 / length, and a
// dot product sums x, y, z in that order.
#include "geometry/pov_triangle.h"

#include <cmath>
#include <utility>

#include "geometry/primitive.h"

namespace pvrt {

namespace {

// The axis of the largest of three magnitudes, ties going as POV-Ray's max3_coordinate:
// x only when strictly above both, else y when strictly above z, else z.
int largestAxis(double x, double y, double z) { return x > y ? (x > z ? 0 : 2) : (y > z ? 1 : 2); }

// v / |v| as POV-Ray's VNormalize: times the reciprocal of the length.
Vec3 unitByReciprocal(const Vec3& v) { return v * (1.0 / length(v)); }

// The two axes a triangle is projected onto when `axis` is its normal's largest.
std::pair<int, int> projection(int axis) { return axis == 0 ? std::pair{1, 2} : axis == 1 ? std::pair{0, 2} : std::pair{0, 1}; }

// Whether (s, t) lies on the outer side of the projected edge from `from` to `to`: the
// sign test POV-Ray makes for each edge and for the winding of its set-up.
bool outside(const Vec3& from, const Vec3& to, double s, double t, int a, int b) {
  return (to[a] - s) * (to[b] - from[b]) < (to[b] - t) * (to[a] - from[a]);
}

}  // namespace

PovTriangleBuilder::PovTriangleBuilder(const Vec3& p1, const Vec3& p2, const Vec3& p3) : p_{p1, p2, p3} { setUp(); }

PovTriangleBuilder::PovTriangleBuilder(const Vec3& p1, const Vec3& n1, const Vec3& p2, const Vec3& n2,
                                       const Vec3& p3, const Vec3& n3)
    : p_{p1, p2, p3}, n_{n1, n2, n3}, smooth_(true) {
  for (Vec3& n : n_) {
    if (length(n) == 0) degenerate_ = true;
    else n = unitByReciprocal(n);
  }
  if (!degenerate_) setUp();
}

void PovTriangleBuilder::scale(const Vec3& s) {
  if (degenerate_) return;
  for (Vec3& p : p_) p = {p.x * s.x, p.y * s.y, p.z * s.z};
  if (smooth_) {
    for (Vec3& n : n_) {
      n = {n.x / s.x, n.y / s.y, n.z / s.z};
      n = unitByReciprocal(n);
    }
  }
  setUp();
}

void PovTriangleBuilder::translate(const Vec3& d) {
  if (degenerate_) return;
  for (Vec3& p : p_) p = p + d;
  setUp();
}

void PovTriangleBuilder::transform(const Affine& toWorld, const Affine& toObject) {
  if (degenerate_) return;
  for (Vec3& p : p_) p = toWorld.applyPoint(p);
  if (smooth_) {
    for (Vec3& n : n_) n = toObject.applyTransposed(n);
  }
  setUp();
}

// Compute_Triangle: the unit face normal from the vertices as they stand, then p1 and p2
// (with their normals) swapped where the projected winding runs the other way, so that
// the edge tests need one sign only. The normal is not recomputed after the swap.
void PovTriangleBuilder::setUp() {
  const Vec3 n = cross(p_[0] - p_[1], p_[2] - p_[1]);
  const double len = length(n);
  if (len == 0) {
    degenerate_ = true;
    return;
  }
  normal_ = n * (1.0 / len);
  const auto [a, b] = projection(largestAxis(std::fabs(normal_.x), std::fabs(normal_.y), std::fabs(normal_.z)));
  if (outside(p_[0], p_[1], p_[2][a], p_[2][b], a, b)) {
    std::swap(p_[0], p_[1]);
    std::swap(n_[0], n_[1]);
  }
  if (smooth_) {
    // Compute_Smooth_Triangle: degenerate unless every vertex normal is on one side.
    const double x = dot(normal_, n_[0]), y = dot(normal_, n_[1]), z = dot(normal_, n_[2]);
    if (!((x < 0 && y < 0 && z < 0) || (x > 0 && y > 0 && z > 0))) degenerate_ = true;
  }
}

std::optional<double> hitPovTriangle(const Vec3& p1, const Vec3& p2, const Vec3& p3, const Vec3& normal,
                                     const Ray& ray, double lo, double hi, double unit) {
  const double nd = dot(normal, ray.dir);
  if (std::fabs(nd) < kPovEpsilon) return std::nullopt;
  const double distance = -dot(normal, p1);  // the plane n.X + distance = 0
  const double t = -(distance + dot(normal, ray.origin)) / nd;
  if (t < kDepthTolerance * unit || t <= lo || t >= hi) return std::nullopt;
  const auto [a, b] = projection(largestAxis(std::fabs(normal.x), std::fabs(normal.y), std::fabs(normal.z)));
  const double s = ray.origin[a] + t * ray.dir[a], u = ray.origin[b] + t * ray.dir[b];
  if (outside(p1, p2, s, u, a, b) || outside(p2, p3, s, u, a, b) || outside(p3, p1, s, u, a, b)) return std::nullopt;
  return t;
}

Vec3 povSmoothNormal(const PovSmoothTriangleShape& tri, const Vec3& at) {
  // Compute_Smooth_Triangle's `Perp`: dotted with (at - p1) it gives the weight u of the
  // edge p2-p3 (0 at p1, 1 on that edge); derived from the vertices each time, so that
  // the shape stays as small as a mesh's smooth triangle.
  const Vec3 p3p2 = tri.p3 - tri.p2;
  const int vAxis = largestAxis(std::fabs(p3p2.x), std::fabs(p3p2.y), std::fabs(p3p2.z));
  const Vec3 edge = unitByReciprocal(tri.p2 - tri.p3);
  const Vec3 toP1 = tri.p1 - tri.p3;
  const Vec3 perpUnit = unitByReciprocal(edge * dot(toP1, edge) - toP1);
  const Vec3 perp = perpUnit * (1.0 / -dot(toP1, perpUnit));

  const Vec3 d = at - tri.p1;
  const double u = dot(d, perp);
  if (u < kPovEpsilon) return tri.n1;
  const double v = (d[vAxis] / u + tri.p1[vAxis] - tri.p2[vAxis]) / (tri.p3[vAxis] - tri.p2[vAxis]);
  Vec3 n;
  for (int i = 0; i < 3; ++i) n[i] = tri.n1[i] + u * (tri.n2[i] - tri.n1[i] + v * (tri.n3[i] - tri.n2[i]));
  return unitByReciprocal(n);
}

SurfacePoint povTrianglePoint(const Vec3& p1, const Vec3& normal, const Vec3& at) {
  // The point moved onto the plane bounds how far the plane is: |at - q| plus q's own
  // bound (and a rounding of that sum).
  const SurfacePoint q = flatSurfacePoint(normal, p1, at);
  return {at, (vabs(at - q.p) + q.error) * (1 + errorGamma(2))};
}

}  // namespace pvrt
