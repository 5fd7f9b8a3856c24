// Errors that reach the user. Each carries the message exactly as it is printed and
// the exit code documented in docs/cli.md.
#pragma once

#include <stdexcept>
#include <string>

#include "core/source_loc.h"

namespace pvrt {

enum class ExitCode : int {
  Ok = 0,
  Usage = 2,       // bad command line
  SceneError = 3,  // the scene file could not be read or is invalid
  OutputError = 4, // the image could not be written
  Interrupted = 130,
  Internal = 70,
};

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

// `file:line: element: what is wrong` (compiler style, so editors can jump to it)
inline Error sceneError(const SourceLoc& loc, const std::string& element, const std::string& what) {
  return Error(ExitCode::SceneError, loc.str() + ": " + element + ": " + what);
}

}  // namespace pvrt
