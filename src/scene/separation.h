// Two points that define a direction (a camera's location and look_at, a spotlight and
// the point it aims at, a cylinder's or cone's base and cap) must lie far enough apart for
// that direction to be the scene's and not rounding's. docs/robustness.md, "Degenerate
// vectors", gives the reasons for both limits.
#pragma once

#include <algorithm>
#include <cmath>
#include <optional>
#include <string>

#include <fmt/core.h>

#include "core/vec3.h"

namespace pvrt {

// Below this share of the points' coordinates their difference is a few thousand ulps:
// its direction is then known only to about 1e-4 radians, a tenth of a pixel of a
// 1000-pixel image one radian wide.
inline constexpr double kMinRelativeSeparation = 1e-12;
// The shortest length of a vector that gives a direction (a normal, the camera's vectors)
// or of a separation: below it, squares and products of such lengths leave the range of a
// double.
inline constexpr double kMinLength = 1e-100;

// Nothing when a and b are far enough apart; else, for an error message after "X must
// differ from Y", how far they must be ("" when they are equal).
inline std::optional<std::string> tooClose(const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const auto maxAbs = [](const Vec3& v) { return std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)}); };
  const double apart = maxAbs(d), size = std::max(maxAbs(a), maxAbs(b));
  if (apart == 0) return "";
  if (apart < kMinRelativeSeparation * size)
    return fmt::format(" by more than {:g} of their coordinates ({:.3g}): they are {:.3g} apart, a direction "
                       "rounding decides",
                       kMinRelativeSeparation, size, apart);
  if (apart < kMinLength)
    return fmt::format(" by more than {:g}: they are {:.3g} apart", kMinLength, apart);
  return std::nullopt;
}

}  // namespace pvrt
