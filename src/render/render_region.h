// The render region of POV-Ray's +SC/+EC/+SR/+ER (`pvrt render --start-col` ...): which
// pixels of the image to render.
#pragma once

#include <string>

#include "parallel/schedule.h"

namespace pvrt {

// The four bounds as given; an empty one is the image's edge.
struct RegionBounds {
  std::string startCol, endCol, startRow, endRow;
  bool any() const { return !startCol.empty() || !endCol.empty() || !startRow.empty() || !endRow.empty(); }
};

// As POV-Ray 3.7 reads them: an integer is a pixel number counted from 1, the end one
// included (`--start-row 11 --end-row 20` is 10 rows); a number with a decimal point from
// 0.0 to 1.0 is a share of the side, the first pixel at floor(share x side), counted from 0,
// and the last before floor(share x side) for an end (0.25 to 0.5 of 64 columns is 16 to
// 31). The result is the rectangle [x0, x1) x [y0, y1). Throws pvrt::Error(Usage) naming
// the option for a value that is not such a number, lies outside the image or leaves
// nothing to render.
WorkItem parseRegion(const RegionBounds& bounds, int width, int height);

}  // namespace pvrt
