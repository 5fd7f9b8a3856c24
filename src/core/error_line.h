// The one line pvrt prints for an Error that ends it (cli/main.cpp, and rank 0 of an MPI run).
#pragma once

#include <string>

#include "core/error.h"

namespace pvrt {

// The line printed for `e`: every error line carries `error:` where editors and CI log
// scanners look for it. A scene error names its file (and line) first, `scene.xml:4: error:
// ...` (export-pov --strict: its warning's line); anything else that does not already start
// with "pvrt" reads as the command-line parser's own errors do, `pvrt: error: ...`, whichever
// part of pvrt found it (--spp 8 is refused by the sampler, -o x.bmp by the image writer, a
// missing folder by the output plan, an unreadable --reference image by the image reader).
inline std::string errorLine(const Error& e) {
  const std::string what = e.what();
  const bool prefixed = what.compare(0, 5, "pvrt:") == 0 || what.compare(0, 5, "pvrt ") == 0;
  // `file:line: error: ...`, or export-pov --strict's `file:line: warning: ... (--strict)`
  const bool named = what.find(": error: ") != std::string::npos || what.find(": warning: ") != std::string::npos;
  return prefixed || named ? what : "pvrt: error: " + what;
}

}  // namespace pvrt
