// The record of a golden run for people and for CI: one self-contained HTML file (every test,
// pictures embedded as PNG data URIs: new | reference | difference xN | the worst area
// enlarged, in a table sortable by any column) and a JUnit XML file.
#pragma once

#include <string>
#include <vector>

#include "golden/outcome.h"

namespace pvrt::golden {

struct ReportOptions {
  std::string title = "pvrt golden";
  std::string hint;      // a line under the title: how to remake or bless references
  int diffScale = 16;    // the difference image is |new - reference| x this
  int zoomSize = 16;     // side of the enlarged worst area, in pixels
};

// Both throw pvrt::Error(OutputError) when the file cannot be written (written atomically).
void writeHtmlReport(const std::vector<Outcome>& outcomes, const std::string& path, const ReportOptions& o);
void writeJunit(const std::vector<Outcome>& outcomes, const std::string& path);

// The top-left corner of the size x size window (clamped to the image) whose summed absolute
// difference is largest; ties go to the first in row order.
void worstWindow(const std::vector<uint8_t>& a, const std::vector<uint8_t>& b, int width, int height, int size,
                 int& x0, int& y0);

}  // namespace pvrt::golden
