// Kernels for effect sets 96 to 127.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels3(RectKernel* table) {
  fillKernels<96>(table, std::make_integer_sequence<EffectSet, 32>{});
}

}  // namespace pvrt
