#include "core/transform.h"

#include <cmath>
#include <numbers>

namespace pvrt {

double Affine::determinant() const {
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
         m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
         m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

Affine Affine::then(const Affine& next) const {
  Affine r;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      r.m[i][j] = next.m[i][0] * m[0][j] + next.m[i][1] * m[1][j] + next.m[i][2] * m[2][j];
  r.t = next.applyPoint(t);
  return r;
}

std::optional<Affine> Affine::inverse() const {
  const double det = determinant();
  double scale = 0;
  for (const auto& row : m)
    for (double v : row) scale = std::fmax(scale, std::fabs(v));
  // Relative test: a matrix whose determinant is tiny next to its entries is degenerate.
  if (!std::isfinite(det) || scale == 0 || std::fabs(det) <= 1e-14 * scale * scale * scale)
    return std::nullopt;
  Affine r;
  const double k = 1.0 / det;
  r.m[0][0] = (m[1][1] * m[2][2] - m[1][2] * m[2][1]) * k;
  r.m[0][1] = (m[0][2] * m[2][1] - m[0][1] * m[2][2]) * k;
  r.m[0][2] = (m[0][1] * m[1][2] - m[0][2] * m[1][1]) * k;
  r.m[1][0] = (m[1][2] * m[2][0] - m[1][0] * m[2][2]) * k;
  r.m[1][1] = (m[0][0] * m[2][2] - m[0][2] * m[2][0]) * k;
  r.m[1][2] = (m[0][2] * m[1][0] - m[0][0] * m[1][2]) * k;
  r.m[2][0] = (m[1][0] * m[2][1] - m[1][1] * m[2][0]) * k;
  r.m[2][1] = (m[0][1] * m[2][0] - m[0][0] * m[2][1]) * k;
  r.m[2][2] = (m[0][0] * m[1][1] - m[0][1] * m[1][0]) * k;
  r.t = -r.applyVector(t);
  return r;
}

bool Affine::isIdentity() const { return *this == Affine{}; }

Affine Affine::scale(const Vec3& s) {
  Affine a;
  a.m = {{{s.x, 0, 0}, {0, s.y, 0}, {0, 0, s.z}}};
  return a;
}

Affine Affine::translate(const Vec3& d) {
  Affine a;
  a.t = d;
  return a;
}

Affine Affine::rotate(const Vec3& degrees) {
  const double k = std::numbers::pi / 180.0;
  auto axis = [](int i, double rad) {
    Affine a;
    const double c = std::cos(rad), s = std::sin(rad);
    const int u = (i + 1) % 3, v = (i + 2) % 3;  // the plane the rotation turns
    a.m[u][u] = c;
    a.m[u][v] = -s;
    a.m[v][u] = s;
    a.m[v][v] = c;
    return a;
  };
  // x first, then y, then z; Ry written with the cyclic (z,x) plane gives
  // x' = x cos + z sin, z' = -x sin + z cos as POV-Ray does.
  return axis(0, degrees.x * k).then(axis(1, degrees.y * k)).then(axis(2, degrees.z * k));
}

Affine Affine::povMatrix(const std::array<double, 12>& v) {
  Affine a;
  for (int row = 0; row < 3; ++row)
    for (int col = 0; col < 3; ++col) a.m[col][row] = v[row * 3 + col];
  a.t = {v[9], v[10], v[11]};
  return a;
}

}  // namespace pvrt
