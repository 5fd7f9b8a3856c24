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
  Stalled = 75,       // MPI: a rank was stopped for longer than --mpi-timeout (cluster::startWatchdog)
  Interrupted = 130,  // SIGINT (128 + 2)
  Terminated = 143,   // SIGTERM (128 + 15)
  Internal = 70,
};

class Error : public std::runtime_error {
 public:
  Error(ExitCode code, const std::string& message) : std::runtime_error(message), code_(code) {}
  ExitCode code() const { return code_; }

 private:
  ExitCode code_;
};

// `file:line: error: element: what is wrong`: compiler style, so editors and CI log
// scanners that look for `: error:` jump to it. `element` and `what` must be one line.
inline Error sceneError(const SourceLoc& loc, const std::string& element, const std::string& what) {
  return Error(ExitCode::SceneError, loc.str() + ": error: " + element + ": " + what);
}

// `file: error: what is wrong`, for a scene that could not be read at all (no line to name).
inline Error sceneFileError(const std::string& file, const std::string& what) {
  return Error(ExitCode::SceneError, printableName(file) + ": error: " + what);
}

}  // namespace pvrt
