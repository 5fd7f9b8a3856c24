// One compiled kernel per combination of kernel effects (2^7 of them), looked up at
// run time once per render.
#pragma once

#include "image/image.h"
#include "parallel/schedule.h"
#include "render/effects.h"
#include "render/sampler.h"
#include "render/scene.h"
#include "render/stats.h"

namespace pvrt {

using RectKernel = void (*)(const Scene&, const PixelSampler&, const WorkItem&, Image&, float* load,
                            RenderStats&);

RectKernel kernelFor(EffectSet effects);

}  // namespace pvrt
