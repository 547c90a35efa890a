#pragma once

// Private: the allocator of the big arrays traversal reads at random (wide BVH nodes, leaf
// blocks, builder scratch). Internal since the wide BVH layout is; never installed.

#include <cstddef>
#include <new>

namespace librt::detail {

/// Allocates `bytes` aligned to `alignment`; large blocks go on 2 MiB boundaries and are
/// advised to use transparent huge pages (Linux), which spares random accesses into big
/// acceleration structures most of their TLB misses. Throws std::bad_alloc.
[[nodiscard]] void* allocate_large(std::size_t bytes, std::size_t alignment);
/// Frees what allocate_large returned for the same `bytes` and `alignment`.
void deallocate_large(void* p, std::size_t bytes, std::size_t alignment) noexcept;

/// A std::allocator replacement for big arrays that are read at random (BVH nodes, leaf
/// blocks): from 1 MiB up, memory is 2 MiB-aligned and asked to live on huge pages, as
/// Embree does for its BVHs. Small arrays get plain aligned operator new.
template <class T>
struct LargePageAllocator {
    using value_type = T;  ///< the element type, as std::allocator_traits requires

    LargePageAllocator() = default;
    /// Stateless: any two allocators are interchangeable.
    template <class U>
    LargePageAllocator(const LargePageAllocator<U>&) noexcept {}

    /// Room for n objects of T (uninitialised).
    [[nodiscard]] T* allocate(std::size_t n) {
        if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
        return static_cast<T*>(allocate_large(n * sizeof(T), alignof(T)));
    }
    /// Frees what allocate(n) returned.
    void deallocate(T* p, std::size_t n) noexcept {
        deallocate_large(p, n * sizeof(T), alignof(T));
    }

    /// Always equal (stateless).
    template <class U>
    bool operator==(const LargePageAllocator<U>&) const noexcept {
        return true;
    }
};

}  // namespace librt::detail
