// Kernels for effect sets 16 to 23.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels2(RectKernel* table) {
  fillKernels<16>(table, std::make_integer_sequence<EffectSet, 8>{});
}

}  // namespace pvrt
