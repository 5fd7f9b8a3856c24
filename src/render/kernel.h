// One compiled kernel per combination of kernel effects (2^7 of them), looked up at
// run time once per render.
#pragma once

#include <cstdint>
#include <vector>

#include "image/image.h"
#include "parallel/schedule.h"
#include "render/effects.h"
#include "render/sampler.h"
#include "render/scene.h"
#include "render/stats.h"

namespace pvrt {

// A render in passes (render/passes.h): each pass traces samples [firstSample, count) of
// every pixel (PixelSampler), and between passes the image holds each pixel's float sum so
// far (PixelSum's fields, exact), which finishPasses() turns into means.
struct PassBuffers {
  bool resume = false;             // the image holds the sums of the samples before this pass
  std::vector<uint8_t> nonFinite;  // per pixel of the full image: it had a non-finite sample
};

// `pass`: null for a render in one go (the image gets each pixel's value).
using RectKernel = void (*)(const Scene&, const PixelSampler&, const WorkItem&, Image&, float* load,
                            RenderStats&, PassBuffers* pass);

RectKernel kernelFor(EffectSet effects);

}  // namespace pvrt
