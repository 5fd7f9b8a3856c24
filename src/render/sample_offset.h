// Where a camera ray goes within its pixel.
#pragma once

namespace pvrt {

struct SubSample {
  double dx, dy;  // offset from the pixel centre, in pixels (dy downward)
};

}  // namespace pvrt
