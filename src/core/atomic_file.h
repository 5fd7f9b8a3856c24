// Writes a whole file or nothing: the bytes go to a temporary file beside the target,
// which is renamed over it only once complete. What the user had is never half-replaced.
#pragma once

#include <string>

namespace pvrt {

// Throws pvrt::Error(ExitCode::OutputError) on failure, leaving no temporary behind.
void writeFileAtomically(const std::string& path, const std::string& bytes);
// A unique temporary name in the target's directory that keeps the target's extension.
std::string temporarySibling(const std::string& path);

}  // namespace pvrt
