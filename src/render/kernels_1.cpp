// Kernels for effect sets 32 to 63.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels1(RectKernel* table) {
  fillKernels<32>(table, std::make_integer_sequence<EffectSet, 32>{});
}

}  // namespace pvrt
