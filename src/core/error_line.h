// The one line pvrt prints for an Error that ends it (cli/main.cpp, and rank 0 of an MPI run).
#pragma once

#include <string>

#include "core/error.h"

namespace pvrt {

// The line printed for `e`: a bad command line, and an output or image that cannot be
// written or read, read as the command-line parser's own errors do, `pvrt: error: ...`,
// whichever part of pvrt found them (--spp 8 is refused by the sampler, -o x.bmp by the image
// writer, a missing folder by the output plan); scene errors name their file and line.
inline std::string errorLine(const Error& e) {
  const std::string what = e.what();
  const bool prefixed = what.compare(0, 5, "pvrt:") == 0 || what.compare(0, 5, "pvrt ") == 0;
  const bool ours = e.code() == ExitCode::Usage || e.code() == ExitCode::OutputError;
  return ours && !prefixed ? "pvrt: error: " + what : what;
}

}  // namespace pvrt
