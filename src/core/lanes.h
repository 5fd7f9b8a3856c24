// Four doubles side by side, one lane per child of a BVH node's quad or per ray of a
// packet, and eight floats, one lane per child of a whole node: an AVX register when the
// compiler targets AVX, two SSE2 registers on any other x86-64, plain numbers elsewhere
// (and when PVRT_LANES_SCALAR is defined, so that this version can be tested too). Every
// operation is the IEEE one lane by lane, so a lane gives exactly the bits the scalar code
// would.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace pvrt::lanes {

#if defined(__AVX__) && !defined(PVRT_LANES_SCALAR)

struct Double4 { __m256d v; };
inline Double4 splat(double s) { return {_mm256_set1_pd(s)}; }
inline Double4 set(double a, double b, double c, double d) { return {_mm256_setr_pd(a, b, c, d)}; }
// Four floats, 16-byte aligned, widened exactly.
inline Double4 widen(const float* p) { return {_mm256_cvtps_pd(_mm_load_ps(p))}; }
inline Double4 operator+(Double4 a, Double4 b) { return {_mm256_add_pd(a.v, b.v)}; }
inline Double4 operator-(Double4 a, Double4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
inline Double4 operator*(Double4 a, Double4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
inline Double4 operator/(Double4 a, Double4 b) { return {_mm256_div_pd(a.v, b.v)}; }
inline Double4 sqrt(Double4 a) { return {_mm256_sqrt_pd(a.v)}; }
inline Double4 load(const double* p) { return {_mm256_loadu_pd(p)}; }
// x > keep ? x : keep, and x < keep ? x : keep: x86's max and min return their second
// operand when the first is NaN, which is what the ternaries do.
inline Double4 maxOr(Double4 x, Double4 keep) { return {_mm256_max_pd(x.v, keep.v)}; }
inline Double4 minOr(Double4 x, Double4 keep) { return {_mm256_min_pd(x.v, keep.v)}; }
inline Double4 abs(Double4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
// std::copysign lane by lane: the magnitude of `mag` with the sign bit of `sign`.
inline Double4 copySign(Double4 mag, Double4 sign) {
  const __m256d s = _mm256_set1_pd(-0.0);
  return {_mm256_or_pd(_mm256_andnot_pd(s, mag.v), _mm256_and_pd(s, sign.v))};
}
// Bit i set when a[i] <= b[i] (false for NaN).
inline unsigned lessEqual(Double4 a, Double4 b) { return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ))); }
inline unsigned less(Double4 a, Double4 b) { return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ))); }
inline void store(double* out, Double4 a) { _mm256_storeu_pd(out, a.v); }
inline Double4 floor(Double4 a) { return {_mm256_floor_pd(a.v)}; }
inline unsigned equal(Double4 a, Double4 b) { return unsigned(_mm256_movemask_pd(_mm256_cmp_pd(a.v, b.v, _CMP_EQ_OQ))); }
// Lane i of a where bit i of `bits` is set, else of b.
inline Double4 select(unsigned bits, Double4 a, Double4 b) {
  const __m256i m = _mm256_setr_epi64x(-int64_t(bits & 1u), -int64_t(bits >> 1 & 1u), -int64_t(bits >> 2 & 1u),
                                       -int64_t(bits >> 3 & 1u));
  return {_mm256_blendv_pd(b.v, a.v, _mm256_castsi256_pd(m))};
}

struct Float8 { __m256 v; };
inline Float8 splat8(float s) { return {_mm256_set1_ps(s)}; }
// Eight floats from two 16-byte aligned groups of four: lanes 0-3 from a, 4-7 from b.
inline Float8 load8(const float* a, const float* b) {
  return {_mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(a)), _mm_load_ps(b), 1)};
}
inline Float8 operator+(Float8 a, Float8 b) { return {_mm256_add_ps(a.v, b.v)}; }
inline Float8 operator-(Float8 a, Float8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
inline Float8 operator*(Float8 a, Float8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
inline Float8 maxOr(Float8 x, Float8 keep) { return {_mm256_max_ps(x.v, keep.v)}; }
inline Float8 minOr(Float8 x, Float8 keep) { return {_mm256_min_ps(x.v, keep.v)}; }
inline unsigned lessEqual(Float8 a, Float8 b) {
  return unsigned(_mm256_movemask_ps(_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)));
}
inline void store(float* out, Float8 a) { _mm256_storeu_ps(out, a.v); }

#elif defined(__SSE2__) && !defined(PVRT_LANES_SCALAR)

struct Double4 { __m128d lo, hi; };
inline Double4 splat(double s) { return {_mm_set1_pd(s), _mm_set1_pd(s)}; }
inline Double4 set(double a, double b, double c, double d) { return {_mm_setr_pd(a, b), _mm_setr_pd(c, d)}; }
inline Double4 widen(const float* p) {
  const __m128 f = _mm_load_ps(p);
  return {_mm_cvtps_pd(f), _mm_cvtps_pd(_mm_movehl_ps(f, f))};
}
inline Double4 operator+(Double4 a, Double4 b) { return {_mm_add_pd(a.lo, b.lo), _mm_add_pd(a.hi, b.hi)}; }
inline Double4 operator-(Double4 a, Double4 b) { return {_mm_sub_pd(a.lo, b.lo), _mm_sub_pd(a.hi, b.hi)}; }
inline Double4 operator*(Double4 a, Double4 b) { return {_mm_mul_pd(a.lo, b.lo), _mm_mul_pd(a.hi, b.hi)}; }
inline Double4 operator/(Double4 a, Double4 b) { return {_mm_div_pd(a.lo, b.lo), _mm_div_pd(a.hi, b.hi)}; }
inline Double4 sqrt(Double4 a) { return {_mm_sqrt_pd(a.lo), _mm_sqrt_pd(a.hi)}; }
inline Double4 load(const double* p) { return {_mm_loadu_pd(p), _mm_loadu_pd(p + 2)}; }
inline Double4 maxOr(Double4 x, Double4 keep) { return {_mm_max_pd(x.lo, keep.lo), _mm_max_pd(x.hi, keep.hi)}; }
inline Double4 minOr(Double4 x, Double4 keep) { return {_mm_min_pd(x.lo, keep.lo), _mm_min_pd(x.hi, keep.hi)}; }
inline Double4 abs(Double4 a) {
  const __m128d sign = _mm_set1_pd(-0.0);
  return {_mm_andnot_pd(sign, a.lo), _mm_andnot_pd(sign, a.hi)};
}
inline Double4 copySign(Double4 mag, Double4 sign) {
  const __m128d s = _mm_set1_pd(-0.0);
  return {_mm_or_pd(_mm_andnot_pd(s, mag.lo), _mm_and_pd(s, sign.lo)),
          _mm_or_pd(_mm_andnot_pd(s, mag.hi), _mm_and_pd(s, sign.hi))};
}
inline unsigned lessEqual(Double4 a, Double4 b) {
  return unsigned(_mm_movemask_pd(_mm_cmple_pd(a.lo, b.lo))) | unsigned(_mm_movemask_pd(_mm_cmple_pd(a.hi, b.hi))) << 2;
}
inline unsigned less(Double4 a, Double4 b) {
  return unsigned(_mm_movemask_pd(_mm_cmplt_pd(a.lo, b.lo))) | unsigned(_mm_movemask_pd(_mm_cmplt_pd(a.hi, b.hi))) << 2;
}
inline void store(double* out, Double4 a) {
  _mm_storeu_pd(out, a.lo);
  _mm_storeu_pd(out + 2, a.hi);
}
inline Double4 floor(Double4 a) {  // SSE2 has no rounding instruction
  double v[4];
  store(v, a);
  return set(std::floor(v[0]), std::floor(v[1]), std::floor(v[2]), std::floor(v[3]));
}
inline unsigned equal(Double4 a, Double4 b) {
  return unsigned(_mm_movemask_pd(_mm_cmpeq_pd(a.lo, b.lo))) | unsigned(_mm_movemask_pd(_mm_cmpeq_pd(a.hi, b.hi))) << 2;
}
inline Double4 select(unsigned bits, Double4 a, Double4 b) {
  const __m128d lo = _mm_castsi128_pd(_mm_set_epi64x(-int64_t(bits >> 1 & 1u), -int64_t(bits & 1u)));
  const __m128d hi = _mm_castsi128_pd(_mm_set_epi64x(-int64_t(bits >> 3 & 1u), -int64_t(bits >> 2 & 1u)));
  return {_mm_or_pd(_mm_and_pd(lo, a.lo), _mm_andnot_pd(lo, b.lo)), _mm_or_pd(_mm_and_pd(hi, a.hi), _mm_andnot_pd(hi, b.hi))};
}

struct Float8 { __m128 lo, hi; };
inline Float8 splat8(float s) { return {_mm_set1_ps(s), _mm_set1_ps(s)}; }
inline Float8 load8(const float* a, const float* b) { return {_mm_load_ps(a), _mm_load_ps(b)}; }
inline Float8 operator+(Float8 a, Float8 b) { return {_mm_add_ps(a.lo, b.lo), _mm_add_ps(a.hi, b.hi)}; }
inline Float8 operator-(Float8 a, Float8 b) { return {_mm_sub_ps(a.lo, b.lo), _mm_sub_ps(a.hi, b.hi)}; }
inline Float8 operator*(Float8 a, Float8 b) { return {_mm_mul_ps(a.lo, b.lo), _mm_mul_ps(a.hi, b.hi)}; }
inline Float8 maxOr(Float8 x, Float8 keep) { return {_mm_max_ps(x.lo, keep.lo), _mm_max_ps(x.hi, keep.hi)}; }
inline Float8 minOr(Float8 x, Float8 keep) { return {_mm_min_ps(x.lo, keep.lo), _mm_min_ps(x.hi, keep.hi)}; }
inline unsigned lessEqual(Float8 a, Float8 b) {
  return unsigned(_mm_movemask_ps(_mm_cmple_ps(a.lo, b.lo))) | unsigned(_mm_movemask_ps(_mm_cmple_ps(a.hi, b.hi))) << 4;
}
inline void store(float* out, Float8 a) {
  _mm_storeu_ps(out, a.lo);
  _mm_storeu_ps(out + 4, a.hi);
}

#else

struct Double4 { double v[4]; };
template <class F>
inline Double4 each(F&& f) {
  Double4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = f(i);
  return r;
}
inline Double4 splat(double s) { return {{s, s, s, s}}; }
inline Double4 set(double a, double b, double c, double d) { return {{a, b, c, d}}; }
inline Double4 widen(const float* p) { return each([&](int i) { return double(p[i]); }); }
inline Double4 operator+(Double4 a, Double4 b) { return each([&](int i) { return a.v[i] + b.v[i]; }); }
inline Double4 operator-(Double4 a, Double4 b) { return each([&](int i) { return a.v[i] - b.v[i]; }); }
inline Double4 operator*(Double4 a, Double4 b) { return each([&](int i) { return a.v[i] * b.v[i]; }); }
inline Double4 operator/(Double4 a, Double4 b) { return each([&](int i) { return a.v[i] / b.v[i]; }); }
inline Double4 sqrt(Double4 a) { return each([&](int i) { return std::sqrt(a.v[i]); }); }
inline Double4 load(const double* p) { return each([&](int i) { return p[i]; }); }
inline Double4 maxOr(Double4 x, Double4 keep) {
  return each([&](int i) { return x.v[i] > keep.v[i] ? x.v[i] : keep.v[i]; });
}
inline Double4 minOr(Double4 x, Double4 keep) {
  return each([&](int i) { return x.v[i] < keep.v[i] ? x.v[i] : keep.v[i]; });
}
inline Double4 abs(Double4 a) { return each([&](int i) { return std::fabs(a.v[i]); }); }
inline Double4 copySign(Double4 mag, Double4 sign) {
  return each([&](int i) { return std::copysign(mag.v[i], sign.v[i]); });
}
inline unsigned lessEqual(Double4 a, Double4 b) {
  unsigned m = 0;
  for (int i = 0; i < 4; ++i) m |= (a.v[i] <= b.v[i] ? 1u : 0u) << i;
  return m;
}
inline unsigned less(Double4 a, Double4 b) {
  unsigned m = 0;
  for (int i = 0; i < 4; ++i) m |= (a.v[i] < b.v[i] ? 1u : 0u) << i;
  return m;
}
inline void store(double* out, Double4 a) { std::memcpy(out, a.v, sizeof a.v); }
inline Double4 floor(Double4 a) { return each([&](int i) { return std::floor(a.v[i]); }); }
inline unsigned equal(Double4 a, Double4 b) {
  unsigned m = 0;
  for (int i = 0; i < 4; ++i) m |= (a.v[i] == b.v[i] ? 1u : 0u) << i;
  return m;
}
inline Double4 select(unsigned bits, Double4 a, Double4 b) {
  return each([&](int i) { return (bits >> i & 1u) != 0 ? a.v[i] : b.v[i]; });
}

struct Float8 { float v[8]; };
template <class F>
inline Float8 each8(F&& f) {
  Float8 r;
  for (int i = 0; i < 8; ++i) r.v[i] = f(i);
  return r;
}
inline Float8 splat8(float s) { return each8([&](int) { return s; }); }
inline Float8 load8(const float* a, const float* b) { return each8([&](int i) { return i < 4 ? a[i] : b[i - 4]; }); }
inline Float8 operator+(Float8 a, Float8 b) { return each8([&](int i) { return a.v[i] + b.v[i]; }); }
inline Float8 operator-(Float8 a, Float8 b) { return each8([&](int i) { return a.v[i] - b.v[i]; }); }
inline Float8 operator*(Float8 a, Float8 b) { return each8([&](int i) { return a.v[i] * b.v[i]; }); }
inline Float8 maxOr(Float8 x, Float8 keep) {
  return each8([&](int i) { return x.v[i] > keep.v[i] ? x.v[i] : keep.v[i]; });
}
inline Float8 minOr(Float8 x, Float8 keep) {
  return each8([&](int i) { return x.v[i] < keep.v[i] ? x.v[i] : keep.v[i]; });
}
inline unsigned lessEqual(Float8 a, Float8 b) {
  unsigned m = 0;
  for (int i = 0; i < 8; ++i) m |= (a.v[i] <= b.v[i] ? 1u : 0u) << i;
  return m;
}
inline void store(float* out, Float8 a) { std::memcpy(out, a.v, sizeof a.v); }

#endif

// The least and the greatest of the four lanes (of lanes with no NaN).
inline double lowest(Double4 a) {
  double v[4];
  store(v, a);
  return std::min(std::min(v[0], v[1]), std::min(v[2], v[3]));
}
inline double highest(Double4 a) {
  double v[4];
  store(v, a);
  return std::max(std::max(v[0], v[1]), std::max(v[2], v[3]));
}

}  // namespace pvrt::lanes
