#include "core/large_page_allocator.h"

#include <algorithm>
#include <cstdlib>

#if defined(__linux__)
#include <sys/mman.h>
#endif

namespace librt::detail {
namespace {

constexpr std::size_t kHugePage = std::size_t{2} << 20;
constexpr std::size_t kLargeThreshold = std::size_t{1} << 20;

/// Large blocks are rounded up to whole huge pages, so madvise covers all of them.
std::size_t large_size(std::size_t bytes) {
    return (bytes + kHugePage - 1) / kHugePage * kHugePage;
}

}  // namespace

void* allocate_large(std::size_t bytes, std::size_t alignment) {
    if (bytes < kLargeThreshold)
        return ::operator new(std::max<std::size_t>(bytes, 1), std::align_val_t(alignment));
    const std::size_t size = large_size(bytes);
    void* p = std::aligned_alloc(std::max(kHugePage, alignment), size);
    if (!p) throw std::bad_alloc();
#if defined(__linux__) && defined(MADV_HUGEPAGE)
    (void)madvise(p, size, MADV_HUGEPAGE);  // a hint: failure only costs speed
#endif
    return p;
}

void deallocate_large(void* p, std::size_t bytes, std::size_t alignment) noexcept {
    if (!p) return;
    if (bytes < kLargeThreshold) {
        ::operator delete(p, std::align_val_t(alignment));
        return;
    }
    std::free(p);
}

}  // namespace librt::detail
