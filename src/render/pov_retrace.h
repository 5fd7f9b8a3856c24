// When a plain pov render must be traced again to make POV-Ray's +A0.0 decisions.
#pragma once

#include "render/sampler.h"

namespace pvrt {

// POV-Ray's +A0.0 +AM1 supersamples a pixel when its colour differs from its left or top
// neighbour's by at least 0 (tracetask.cpp, NonAdaptiveSupersamplingForOnePixel): every
// pixel, unless a colour is NaN (or two neighbours are infinite in one channel), when the
// difference is NaN and the comparison fails, so that such a pixel keeps its centre ray
// alone. The plain pov sampler supersamples every pixel, which is POV-Ray's image only while
// every sample is finite: a render with these settings that meets a NaN or infinite sample
// is traced again through the +AM1 block kernel (as --pov-blocks), which makes POV-Ray's
// decisions, on every backend.
inline bool retraceNonFiniteAsPovBlocks(const SamplerSettings& s) {
  return s.kind == SamplerKind::Pov && s.samplesPerPixel > 1 && s.firstSample == 0 && s.adaptive.threshold == 0 &&
         s.adaptive.method == 1 && !s.adaptive.blocks;
}

}  // namespace pvrt
