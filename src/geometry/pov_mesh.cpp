// POV-Ray 3.7's Mesh (source/backend/shape/mesh.cpp) and the triangles of Parse_Mesh
// (parser/parse.cpp): the same operations in the same order and the same precision, since
// their rounding decides pixels. Vector helpers as POV-Ray's (math/vector.h): a dot product
// sums x, y, z in that order, a vector is made unit by multiplying with 1 / length, and the
// helpers that write a float vector (SNGL_VECT) round each component there and, for float
// operands, compute in float.
#include "geometry/pov_mesh.h"

#include <cmath>
#include <utility>

#include "core/single.h"

namespace pvrt {

namespace {

constexpr double kEpsilon = 1e-10;  // POV-Ray's EPSILON
constexpr int kHashSize = 1000;     // mesh.cpp's HASH_SIZE

// x rounded to a float that the optimiser may not fold away (core/single.h).
float toFloat(double x) { return float(single(x)); }

// max3_coordinate: x only when strictly above both, else y when strictly above z, else z.
uint8_t largestAxis(double x, double y, double z) { return x > y ? (x > z ? 0 : 2) : (y > z ? 1 : 2); }

// The two axes a triangle is projected onto when `axis` is its normal's largest.
std::pair<int, int> projection(int axis) {
  return axis == 0 ? std::pair{1, 2} : axis == 1 ? std::pair{0, 2} : std::pair{0, 1};
}

double dot3(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

// VNormalize on doubles: times 1 / length.
Vec3 unitByReciprocal(const Vec3& v) {
  const double k = 1.0 / std::sqrt(v.x * v.x + v.y * v.y + v.z * v.z);
  return {v.x * k, v.y * k, v.z * k};
}

// (int) of a double as x86-64 converts it: out of range (or NaN) gives INT_MIN.
int truncated(double x) { return x > -2147483649.0 && x < 2147483648.0 ? int(x) : int(0x80000000u); }

}  // namespace

PovMeshBuilder::PovMeshBuilder() = default;

PovMeshBuilder::Table::Table() : buckets_(kHashSize) {}

std::array<float, 3> PovMeshBuilder::Table::find(const Vec3& v) {
  const std::array<float, 3> p{toFloat(v.x), toFloat(v.y), toFloat(v.z)};
  const unsigned key = unsigned(truncated(326.0 * p[0]) ^ truncated(694.7 * p[1]) ^ truncated(1423.6 * p[2]));
  std::vector<uint32_t>& bucket = buckets_[key % kHashSize];
  // The newest entry first: POV-Ray puts each new one at the head of its bucket's list.
  for (auto it = bucket.rbegin(); it != bucket.rend(); ++it) {
    const std::array<float, 3>& q = values_[*it];
    const float d0 = q[0] - p[0], d1 = q[1] - p[1], d2 = q[2] - p[2];
    if (std::fabs(d0) < kEpsilon && std::fabs(d1) < kEpsilon && std::fabs(d2) < kEpsilon) return q;
  }
  bucket.push_back(uint32_t(values_.size()));
  values_.push_back(p);
  return p;
}

namespace {

// Mesh::Degenerate: (p1 - p2) x (p3 - p2) of length 0.
bool degenerate(const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  const Vec3 a = p1 - p2, b = p3 - p2;
  const Vec3 c{a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
  return std::sqrt(c.x * c.x + c.y * c.y + c.z * c.z) == 0.0;
}

void store(float (&to)[3], const std::array<float, 3>& from) {
  to[0] = from[0];
  to[1] = from[1];
  to[2] = from[2];
}

}  // namespace

bool PovMeshBuilder::setUp(PovMeshTriangleShape& t, Vec3 p1, Vec3 p2, Vec3 p3, bool& swapped,
                           std::array<float, 3>* perp, uint8_t* vAxis) {
  swapped = false;
  // The face normal (p3 - p1) x (p2 - p1) made unit, the plane's distance from it and p1.
  const Vec3 v1 = p2 - p1, v2 = p3 - p1;
  Vec3 n{v2.y * v1.z - v2.z * v1.y, v2.z * v1.x - v2.x * v1.z, v2.x * v1.y - v2.y * v1.x};
  const double length = std::sqrt(n.x * n.x + n.y * n.y + n.z * n.z);
  if (length == 0.0) {
    store(t.normal, normals_.find(n));  // a zero normal: never hit (|N.D| < EPSILON)
    t.axis = PovMeshTriangleShape::kNever;
    return false;
  }
  const double k = 1.0 / length;
  n = {n.x * k, n.y * k, n.z * k};
  t.distance = -toFloat(dot3(n, p1));
  t.axis = largestAxis(std::fabs(n.x), std::fabs(n.y), std::fabs(n.z));
  const auto [a, b] = projection(t.axis);
  if ((p2[a] - p3[a]) * (p2[b] - p1[b]) < (p2[b] - p3[b]) * (p2[a] - p1[a])) {
    std::swap(p1, p2);
    swapped = true;
  }
  if (perp) {
    // compute_smooth_triangle: Perp is a float vector, made unit and scaled in float.
    const Vec3 p3p2 = p3 - p2;
    *vAxis = largestAxis(std::fabs(p3p2.x), std::fabs(p3p2.y), std::fabs(p3p2.z));
    Vec3 t1 = unitByReciprocal(p2 - p3);
    const Vec3 t2 = p1 - p3;
    const double proj = dot3(t2, t1);
    t1 = {t1.x * proj, t1.y * proj, t1.z * proj};
    float q[3] = {toFloat(t1.x - t2.x), toFloat(t1.y - t2.y), toFloat(t1.z - t2.z)};
    const float sum = q[0] * q[0] + q[1] * q[1] + q[2] * q[2];
    const float len = std::sqrt(sum);
    const float inv = toFloat(1.0 / double(len));
    for (float& c : q) c *= inv;
    const double uDenominator = t2.x * double(q[0]) + t2.y * double(q[1]) + t2.z * double(q[2]);
    const float scale = toFloat(-uDenominator);
    const float invScale = toFloat(1.0 / double(scale));
    for (float& c : q) c *= invScale;
    *perp = {q[0], q[1], q[2]};
  }
  store(t.normal, normals_.find(n));
  return true;
}

PovMeshTriangleShape PovMeshBuilder::triangle(const Vec3& p1, const Vec3& p2, const Vec3& p3) {
  PovMeshTriangleShape t;
  if (degenerate(p1, p2, p3)) {
    // Left out by the parser: never hit, its corners kept for its bounds alone.
    for (int i = 0; i < 3; ++i) {
      const Vec3& p = i == 0 ? p1 : i == 1 ? p2 : p3;
      t.p[i][0] = toFloat(p.x), t.p[i][1] = toFloat(p.y), t.p[i][2] = toFloat(p.z);
    }
    return t;
  }
  std::array<float, 3> c[3] = {vertices_.find(p1), vertices_.find(p2), vertices_.find(p3)};
  bool swapped = false;
  setUp(t, p1, p2, p3, swapped, nullptr, nullptr);
  if (swapped) std::swap(c[0], c[1]);
  for (int i = 0; i < 3; ++i) store(t.p[i], c[i]);
  return t;
}

PovMeshSmoothTriangleShape PovMeshBuilder::smoothTriangle(const Vec3& p1, Vec3 n1, const Vec3& p2, Vec3 n2,
                                                          const Vec3& p3, Vec3 n3, bool& smooth) {
  PovMeshSmoothTriangleShape t;
  smooth = false;
  // A zero normal (every coordinate within EPSILON of 0) becomes one with x = 1.
  for (Vec3* n : {&n1, &n2, &n3})
    if (std::fabs(n->x) < kEpsilon && std::fabs(n->y) < kEpsilon && std::fabs(n->z) < kEpsilon) n->x = 1.0;
  const double l1 = std::sqrt(dot3(n1, n1)), l2 = std::sqrt(dot3(n2, n2)), l3 = std::sqrt(dot3(n3, n3));
  if (l1 == 0.0 || l2 == 0.0 || l3 == 0.0 || degenerate(p1, p2, p3)) {
    for (int i = 0; i < 3; ++i) {
      const Vec3& p = i == 0 ? p1 : i == 1 ? p2 : p3;
      t.p[i][0] = toFloat(p.x), t.p[i][1] = toFloat(p.y), t.p[i][2] = toFloat(p.z);
    }
    return t;
  }
  const auto inverseScale = [](const Vec3& v, double l) {
    const double k = 1.0 / l;
    return Vec3{v.x * k, v.y * k, v.z * k};
  };
  n1 = inverseScale(n1, l1);
  n2 = inverseScale(n2, l2);
  n3 = inverseScale(n3, l3);
  std::array<float, 3> c[3] = {vertices_.find(p1), vertices_.find(p2), vertices_.find(p3)};
  const Vec3 d1 = n1 - n2, d2 = n1 - n3;
  smooth = std::fabs(dot3(d1, d1)) > kEpsilon || std::fabs(dot3(d2, d2)) > kEpsilon;
  std::array<float, 3> n[3];
  if (smooth) n[0] = normals_.find(n1), n[1] = normals_.find(n2), n[2] = normals_.find(n3);
  bool swapped = false;
  std::array<float, 3> perp{};
  setUp(t, p1, p2, p3, swapped, &perp, &t.vAxis);
  if (swapped) {
    std::swap(c[0], c[1]);
    std::swap(n[0], n[1]);
  }
  for (int i = 0; i < 3; ++i) store(t.p[i], c[i]);
  if (smooth) {
    for (int i = 0; i < 3; ++i) store(t.n[i], n[i]);
    store(t.perp, perp);
  }
  return t;
}

std::optional<double> hitPovMeshTriangle(const PovMeshTriangleShape& t, const Vec3& origin, const Vec3& dir,
                                         double minDepth) {
  if (t.axis == PovMeshTriangleShape::kNever) return std::nullopt;
  const Vec3 n = t.faceNormal();
  const double nd = dot3(n, dir);
  if (std::fabs(nd) < kEpsilon) return std::nullopt;
  const double no = dot3(n, origin);
  const double depth = -(double(t.distance) + no) / nd;
  if (depth < minDepth) return std::nullopt;
  const auto [a, b] = projection(t.axis);
  const double s = origin[a] + depth * dir[a], u = origin[b] + depth * dir[b];
  const Vec3 p1 = t.corner(0), p2 = t.corner(1), p3 = t.corner(2);
  if ((p2[a] - s) * (p2[b] - p1[b]) < (p2[b] - u) * (p2[a] - p1[a])) return std::nullopt;
  if ((p3[a] - s) * (p3[b] - p2[b]) < (p3[b] - u) * (p3[a] - p2[a])) return std::nullopt;
  if ((p1[a] - s) * (p1[b] - p3[b]) < (p1[b] - u) * (p1[a] - p3[a])) return std::nullopt;
  return depth;
}

Vec3 povSmoothMeshNormal(const PovMeshSmoothTriangleShape& t, const Vec3& at) {
  const Vec3 n1 = t.vertexNormal(0), n2 = t.vertexNormal(1), n3 = t.vertexNormal(2);
  const Vec3 p1 = t.corner(0);
  const Vec3 d = at - p1;
  const double u = d.x * double(t.perp[0]) + d.y * double(t.perp[1]) + d.z * double(t.perp[2]);
  if (u < kEpsilon) return n1;
  const int axis = t.vAxis;
  const double k1 = t.p[0][axis], k2 = t.p[1][axis], k3 = t.p[2][axis];
  const double v = (d[axis] / u + k1 - k2) / (k3 - k2);
  Vec3 r;
  for (int i = 0; i < 3; ++i) r[i] = n1[i] + u * (n2[i] - n1[i] + v * (n3[i] - n2[i]));
  return r;
}

}  // namespace pvrt
