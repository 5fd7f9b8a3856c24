#include "render/render_region.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include "core/decimal_text.h"
#include "core/error.h"

namespace pvrt {

namespace {

Error bad(const char* option, const std::string& value, const std::string& why) {
  return Error(ExitCode::Usage, std::string("pvrt: error: ") + option + " " + value + ": " + why);
}

// One bound as a pixel index counted from 0: the first pixel for a start, one past the last
// for an end.
int bound(const std::string& value, int side, bool end, const char* option) {
  const bool share = value.find('.') != std::string::npos;
  const char* begin = value.c_str();
  char* stop = nullptr;
  errno = 0;
  const double v = share ? std::strtod(begin, &stop) : double(std::strtol(begin, &stop, 10));
  // Decimal digits only, as every number pvrt reads: strtol and strtod alone also take " 2",
  // "+2" and a hexadecimal share ("0x0.8p0").
  const bool decimal = share ? isDecimalNumber(value) : canonicalWholeNumber(value).has_value();
  if (!decimal || stop != begin + value.size() || errno != 0 || !std::isfinite(v))
    throw bad(option, value, "expected a pixel number (1, 2, ...) or a share of the image from 0.0 to 1.0");
  if (share) {
    if (v < 0 || v > 1) throw bad(option, value, "a share of the image must lie from 0.0 to 1.0");
    return int(std::floor(v * side));
  }
  if (v < 1 || v > side)
    throw bad(option, value, "pixel numbers run from 1 to " + std::to_string(side) + " on this side");
  return end ? int(v) : int(v) - 1;
}

}  // namespace

WorkItem parseRegion(const RegionBounds& b, int width, int height) {
  WorkItem r{0, 0, width, height};
  if (!b.startCol.empty()) r.x0 = bound(b.startCol, width, false, "--start-col");
  if (!b.endCol.empty()) r.x1 = bound(b.endCol, width, true, "--end-col");
  if (!b.startRow.empty()) r.y0 = bound(b.startRow, height, false, "--start-row");
  if (!b.endRow.empty()) r.y1 = bound(b.endRow, height, true, "--end-row");
  if (r.x0 >= r.x1)
    throw Error(ExitCode::Usage, "pvrt: error: the region's columns " + std::to_string(r.x0 + 1) + " to " +
                                     std::to_string(r.x1) + " hold no pixel (--start-col is after --end-col)");
  if (r.y0 >= r.y1)
    throw Error(ExitCode::Usage, "pvrt: error: the region's rows " + std::to_string(r.y0 + 1) + " to " +
                                     std::to_string(r.y1) + " hold no pixel (--start-row is after --end-row)");
  return r;
}

}  // namespace pvrt
