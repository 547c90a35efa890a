#include "wide_kernels.h"

namespace librt::detail {

WideKernels wide_kernels(SimdPath path) {
    switch (path) {
#if defined(LIBRT_HAVE_X86_KERNELS)
        case SimdPath::Sse:
            return {&sse::intersect, &sse::occluded};
        case SimdPath::Avx2:
            return {&avx2::intersect, &avx2::occluded};
        case SimdPath::Avx512:
            return {&avx512::intersect, &avx512::occluded};
#endif
        default:
            return {&scalar::intersect, &scalar::occluded};
    }
}

}  // namespace librt::detail
