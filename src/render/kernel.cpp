#include "render/kernel.h"

#include <array>

namespace pvrt {

void fillKernels0(RectKernel* table);
void fillKernels1(RectKernel* table);
void fillKernels2(RectKernel* table);
void fillKernels3(RectKernel* table);

RectKernel kernelFor(EffectSet effects) {
  static const std::array<RectKernel, kKernelEffects + 1> table = [] {
    std::array<RectKernel, kKernelEffects + 1> t{};
    fillKernels0(t.data());
    fillKernels1(t.data());
    fillKernels2(t.data());
    fillKernels3(t.data());
    return t;
  }();
  return table[effects & kKernelEffects];
}

}  // namespace pvrt
