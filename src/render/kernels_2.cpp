// Kernels for effect sets 64 to 95.
#include <utility>

#include "render/kernel_impl.h"

namespace pvrt {

void fillKernels2(RectKernel* table) {
  fillKernels<64>(table, std::make_integer_sequence<EffectSet, 32>{});
}

}  // namespace pvrt
