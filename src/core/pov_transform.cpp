#include "core/pov_transform.h"

#include <cmath>
#include <numbers>

namespace pvrt {

namespace {

using Matrix = PovTransform::Matrix;

Matrix identityMatrix() {
  Matrix m{};
  for (int i = 0; i < 4; ++i) m[i][i] = 1;
  return m;
}

Matrix transposed(const Matrix& m) {
  Matrix t;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t[i][j] = m[j][i];
  return t;
}

// a b, each element summed over k = 0..3 in order (MTimesA and MTimesB both do so).
Matrix product(const Matrix& a, const Matrix& b) {
  Matrix r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) r[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j] + a[i][3] * b[3][j];
  return r;
}

// The row-vector matrix of a column-vector Affine, and back.
Matrix rowForm(const Affine& a) {
  Matrix m = identityMatrix();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) m[j][i] = a.m[i][j];
    m[3][i] = a.t[i];
  }
  return m;
}
Affine columnForm(const Matrix& m) {
  Affine a;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) a.m[i][j] = m[j][i];
    a.t[i] = m[3][i];
  }
  return a;
}

}  // namespace

PovTransform PovTransform::identity() { return {identityMatrix(), identityMatrix()}; }

PovTransform PovTransform::scaling(const Vec3& s) {
  PovTransform t = identity();
  for (int i = 0; i < 3; ++i) {
    t.matrix[i][i] = s[i];
    t.inverse[i][i] = 1.0 / s[i];
  }
  return t;
}

PovTransform PovTransform::translation(const Vec3& d) {
  PovTransform t = identity();
  for (int i = 0; i < 3; ++i) {
    t.matrix[3][i] = d[i];
    t.inverse[3][i] = -d[i];
  }
  return t;
}

PovTransform PovTransform::rotation(const Vec3& degrees) {
  // One turn per axis in the plane of the other two, composed x, y, z; each turn's
  // inverse is its transpose, so the inverse is the product of those in reverse.
  const double k = std::numbers::pi / 180.0;  // POV-Ray's M_PI_180 is this double
  PovTransform r = identity();
  for (int axis = 0; axis < 3; ++axis) {
    const double rad = degrees[axis] * k;
    const double c = std::cos(rad), s = std::sin(rad);
    // POV-Ray's signs: x turns y toward z, y turns z toward x, z turns x toward y.
    const int u = axis == 1 ? 2 : (axis + 1) % 3, v = axis == 1 ? 0 : (axis + 2) % 3;
    Matrix turn = identityMatrix();
    turn[u][u] = c;
    turn[v][v] = c;
    turn[u][v] = s;
    turn[v][u] = 0.0 - s;
    if (axis == 0) {
      r.matrix = turn;
      r.inverse = transposed(turn);
    } else {
      r.matrix = product(r.matrix, turn);
      r.inverse = product(transposed(turn), r.inverse);
    }
  }
  return r;
}

PovTransform PovTransform::axisRotation(const Vec3& axis, double radians) {
  const Vec3 v = axis * (1.0 / length(axis));
  const double c = std::cos(radians), s = std::sin(radians);
  PovTransform t = identity();
  Matrix& m = t.matrix;
  m[0][0] = v.x * v.x + c * (1.0 - v.x * v.x);
  m[0][1] = v.x * v.y * (1.0 - c) + v.z * s;
  m[0][2] = v.x * v.z * (1.0 - c) - v.y * s;
  m[1][0] = v.x * v.y * (1.0 - c) - v.z * s;
  m[1][1] = v.y * v.y + c * (1.0 - v.y * v.y);
  m[1][2] = v.y * v.z * (1.0 - c) + v.x * s;
  m[2][0] = v.x * v.z * (1.0 - c) + v.y * s;
  m[2][1] = v.y * v.z * (1.0 - c) - v.x * s;
  m[2][2] = v.z * v.z + c * (1.0 - v.z * v.z);
  t.inverse = transposed(m);
  return t;
}

PovTransform PovTransform::matrixOf(const Affine& toWorld) {
  const Matrix m = rowForm(toWorld);
  // The determinant of m without row `row` and column `col`, its six products summed in
  // MInvers's order: the three "diagonals" down, then the three up.
  auto minor = [&m](int row, int col) {
    int r[3], c[3];
    for (int i = 0, k = 0; i < 4; ++i)
      if (i != row) r[k++] = i;
    for (int j = 0, k = 0; j < 4; ++j)
      if (j != col) c[k++] = j;
    return m[r[0]][c[0]] * m[r[1]][c[1]] * m[r[2]][c[2]] + m[r[0]][c[1]] * m[r[1]][c[2]] * m[r[2]][c[0]] +
           m[r[0]][c[2]] * m[r[1]][c[0]] * m[r[2]][c[1]] - m[r[2]][c[0]] * m[r[1]][c[1]] * m[r[0]][c[2]] -
           m[r[2]][c[1]] * m[r[1]][c[2]] * m[r[0]][c[0]] - m[r[2]][c[2]] * m[r[1]][c[0]] * m[r[0]][c[1]];
  };
  Matrix d;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) d[i][j] = minor(i, j);
  const double det = m[0][0] * d[0][0] - m[0][1] * d[0][1] + m[0][2] * d[0][2] - m[0][3] * d[0][3];
  PovTransform t{m, {}};
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) t.inverse[i][j] = ((i + j) % 2 ? -d[j][i] : d[j][i]) / det;
  return t;
}

PovTransform PovTransform::coordinate(const Vec3& origin, Vec3 up, double radius, double length) {
  PovTransform t = scaling({radius, radius, length});
  Vec3 turnAxis{-up.y, up.x, 0.0};
  if (std::fabs(up.z) > 1.0 - 1e-10) {  // along z already: POV-Ray's EPSILON
    turnAxis = {1.0, 0.0, 0.0};
    up.z = up.z < 0.0 ? -1.0 : 1.0;
  }
  t.then(axisRotation(turnAxis, std::acos(up.z)));
  t.then(translation(origin));
  return t;
}

void PovTransform::then(const PovTransform& next) {
  matrix = product(matrix, next.matrix);
  inverse = product(next.inverse, inverse);
}

Transform PovTransform::toTransform() const { return {columnForm(matrix), columnForm(inverse)}; }

}  // namespace pvrt
