// Writes a whole file or nothing, for a command with one output: the bytes go to a
// temporary file (core/output_files.h) that replaces the target only once complete.
#pragma once

#include <string>

namespace pvrt {

// Throws pvrt::Error(ExitCode::OutputError) on failure, leaving no temporary behind.
void writeFileAtomically(const std::string& path, const std::string& bytes);

}  // namespace pvrt
