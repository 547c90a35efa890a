#include "wide_kernels.h"

namespace librt::detail {

WideKernels wide_kernels(SimdPath path) {
    switch (path) {
#if defined(LIBRT_HAVE_X86_KERNELS)
        case SimdPath::Sse:
            return sse_wide_kernels();
        case SimdPath::Avx2:
            return avx2_wide_kernels();
        case SimdPath::Avx512:
            return avx512_wide_kernels();
#endif
        default:
            return scalar_wide_kernels();
    }
}

}  // namespace librt::detail
