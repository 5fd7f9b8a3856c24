// Kernels for effect sets 24 to 31.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels3(RectKernel* table) {
  fillKernels<24>(table, std::make_integer_sequence<EffectSet, 8>{});
}

}  // namespace pvrt
