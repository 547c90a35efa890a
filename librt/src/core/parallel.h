#pragma once

// Internal helpers for the builders' data-parallel loops and scratch arrays.

#include "core/large_page_allocator.h"

#include <algorithm>
#include <cstddef>
#include <exception>
#include <memory>
#include <new>
#include <thread>
#include <type_traits>
#include <vector>

namespace librt::detail {

/// Runs body(part, begin, end) over [0, n) cut into `parts` contiguous pieces, one thread
/// each (the calling thread takes part 0); inline when parts is 1. Part p covers
/// [n p / parts, n (p + 1) / parts), so the split depends only on n and parts. Parts whose
/// thread cannot be started (no memory for its stack) run on the calling thread, and an
/// exception from any part is rethrown here after every thread has joined: under a memory
/// limit a build fails with bad_alloc, never std::terminate.
template <class Body>
void parallel_parts(std::size_t n, unsigned parts, Body&& body) {
    parts = std::max(1u, parts);
    std::vector<std::exception_ptr> errors(parts);
    const auto run = [&](unsigned p) noexcept {
        try {
            body(p, n * p / parts, n * (p + 1) / parts);
        } catch (...) {
            errors[p] = std::current_exception();
        }
    };
    std::vector<std::thread> helpers;
    try {
        helpers.reserve(parts - 1);
    } catch (const std::bad_alloc&) {
        // No room for the handles: every part runs here.
    }
    unsigned started = 1;
    // Never past the capacity: a reallocation that failed would destroy a running thread.
    try {
        for (; started < parts && helpers.size() < helpers.capacity(); ++started)
            helpers.emplace_back(run, started);
    } catch (const std::exception&) {
        // The thread did not start (system_error, or bad_alloc for its state); it and the
        // rest run here, and the threads already running are joined below.
    }
    run(0);
    for (unsigned p = started; p < parts; ++p) run(p);
    for (std::thread& h : helpers) h.join();
    for (const std::exception_ptr& e : errors)
        if (e) std::rethrow_exception(e);
}

/// How many threads a loop over n items gets: one below `grain` items (thread start-up
/// costs more than it saves), else every hardware thread.
[[nodiscard]] inline unsigned threads_for(std::size_t n, std::size_t grain = 65536) {
    return n < grain ? 1u : std::max(1u, std::thread::hardware_concurrency());
}

/// Frees a LargeBuffer.
template <class T>
struct LargeFree {
    std::size_t count = 0;
    void operator()(T* p) const noexcept { LargePageAllocator<T>().deallocate(p, count); }
};

/// An uninitialised array on (transparent) huge pages, for build-time scratch arrays of
/// tens of megabytes: on 4 KiB pages the kernel's page faults on first touch cost about a
/// tenth of a large build. T must be trivially destructible; elements are created with
/// std::construct_at (or, for implicit-lifetime aggregates, by assignment).
template <class T>
requires std::is_trivially_destructible_v<T>
using LargeBuffer = std::unique_ptr<T[], LargeFree<T>>;

/// A LargeBuffer of `count` elements, not initialised.
template <class T>
[[nodiscard]] LargeBuffer<T> make_large_buffer(std::size_t count) {
    return LargeBuffer<T>(LargePageAllocator<T>().allocate(std::max<std::size_t>(count, 1)),
                          LargeFree<T>{std::max<std::size_t>(count, 1)});
}

}  // namespace librt::detail
