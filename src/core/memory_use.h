// How much memory this process holds, for --stats: where a big scene's bytes go, stage by
// stage (docs/parallel.md, "Memory").
#pragma once

#include <cstddef>

namespace pvrt {

// The most resident memory this process has held so far (getrusage's maximum RSS), in bytes.
size_t peakResidentBytes();

}  // namespace pvrt
