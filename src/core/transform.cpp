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
  if (!std::isfinite(det) || det == 0) return std::nullopt;
  // Relative test, blind to each axis's own scale: |det| against the product of the rows'
  // lengths and against that of the columns' (Hadamard: each product is at least |det|, and
  // equal to it when the rows, or the columns, are orthogonal). A degenerate matrix has rows
  // that nearly depend on each other and columns that do too. A scale of 1e9 along one axis
  // only, or one turned before or after such a scale, is not: its rows or its columns are
  // orthogonal. (Against the largest entry cubed, scale <1e9, 1, 1> counted as singular.)
  double rowRatio = std::fabs(det), colRatio = std::fabs(det);
  for (int i = 0; i < 3; ++i) {
    const double row = std::hypot(m[i][0], m[i][1], m[i][2]);
    const double col = std::hypot(m[0][i], m[1][i], m[2][i]);
    if (row == 0 || col == 0) return std::nullopt;
    rowRatio /= row;
    colRatio /= col;
  }
  if (rowRatio <= 1e-14 && colRatio <= 1e-14) return std::nullopt;
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
