// Kernels for effect sets 8 to 15.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels1(RectKernel* table) {
  fillKernels<8>(table, std::make_integer_sequence<EffectSet, 8>{});
}

}  // namespace pvrt
