// Kernels for effect sets 0 to 7.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels0(RectKernel* table) {
  fillKernels<0>(table, std::make_integer_sequence<EffectSet, 8>{});
}

}  // namespace pvrt
