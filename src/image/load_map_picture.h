// The load map as a picture (`pvrt render --load-map PREFIX` writes it to PREFIX.png), like
// the paper's figures 4 and 5: each pixel's work in log-scale false colour (dark blue: the
// cheapest pixel, yellow-white: the dearest), and under the map a colour bar whose ticks
// are labelled with work counts, so that the picture can be read without the EXR.
#pragma once

#include <string>
#include <vector>

#include "image/image.h"

namespace pvrt {

// The false colour of work v when the map runs from lo to hi (log scale between them).
Color loadMapColour(double v, double lo, double hi);

// Work counts as tick labels: 950, 12k, 3.4M, 1.2G (at most 4 characters, rounded).
std::string compactCount(double v);

// The map (width x height, row-major work counts) and below it the colour bar: a strip of
// barHeight(width) rows with the ramp from the least work to the most, ticks at the ends and
// at powers of ten between, each labelled where its text fits (digits of a built-in 3 x 5
// bitmap font, twice as big on maps 320 or more wide). The picture is as wide as the map.
Image loadMapPicture(const std::vector<float>& load, int width, int height);

// Rows the colour bar adds under a map `width` wide.
int colourBarRows(int width);

}  // namespace pvrt
