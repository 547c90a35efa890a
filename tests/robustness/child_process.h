#pragma once

// Running a piece of a test in a forked child: its peak memory is then its own, and it
// may run under an address-space limit (RLIMIT_AS) to make allocations fail. Used by the
// loading-memory tests (issue 37, defect 2).

#include "robustness/robustness_util.h"

#include <librt/core/error.h>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

// Sanitizers reserve terabytes of address space (RLIMIT_AS cannot limit them) and add
// shadow memory to the resident size: the memory tests skip there, saying so.
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define LIBRT_TEST_SANITIZED 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define LIBRT_TEST_SANITIZED 1
#endif
#endif

namespace librt::testing {

/// Resident bytes of this process now (/proc/self/statm, field 2, in pages).
inline std::uint64_t resident_bytes() {
    std::ifstream statm("/proc/self/statm");
    std::uint64_t size = 0, resident = 0;
    statm >> size >> resident;
    return resident * std::uint64_t(::sysconf(_SC_PAGESIZE));
}

/// Address space of this process now (/proc/self/statm, field 1, in pages): the base an
/// RLIMIT_AS for a child is set above.
inline std::uint64_t address_space_bytes() {
    std::ifstream statm("/proc/self/statm");
    std::uint64_t size = 0;
    statm >> size;
    return size * std::uint64_t(::sysconf(_SC_PAGESIZE));
}

/// Limits this process's address space (RLIMIT_AS) to what it maps now plus `headroom`
/// bytes of new mappings. Free heap that earlier tests left behind needs no new address
/// space, so it would be used first and whether the limit bites would depend on which tests
/// ran before: with no new mappings allowed it is all taken (and never freed) first, then
/// the headroom is given. Blocks of 1 MiB or more are mapped afresh (glibc's threshold
/// would otherwise have grown to 32 MiB).
inline void limit_address_space(std::uint64_t headroom) {
    ::mallopt(M_MMAP_THRESHOLD, 1 << 20);
    rlimit lim{};
    ::getrlimit(RLIMIT_AS, &lim);
    const rlimit none{address_space_bytes(), lim.rlim_max};
    ::setrlimit(RLIMIT_AS, &none);
    for (std::size_t size = std::size_t{1} << 30u; size >= 16; size /= 2)
        while (std::malloc(size) != nullptr) {
        }
    const rlimit limited{address_space_bytes() + headroom, lim.rlim_max};
    ::setrlimit(RLIMIT_AS, &limited);
}

/// What a child run by in_child did.
struct ChildResult {
    int exit_code = -1;            ///< 0: returned, 1: librt::Error, other: crashed
    std::uint64_t peak_added = 0;  ///< the child's peak resident bytes above the parent's
    std::string message;           ///< the error's message
};

/// Runs f in a child process (so its peak memory is its own), under an address-space
/// limit of its size plus `headroom` bytes when `headroom` is not 0. Any exception but a
/// librt::Error ends the child through std::terminate (SIGABRT): the test sees a crash.
inline ChildResult in_child(const std::function<void()>& f, std::uint64_t headroom = 0) {
    ScratchDir dir;
    const std::filesystem::path message_file = dir.path() / "message";
    const std::uint64_t base = resident_bytes();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid == 0) {
        if (headroom != 0) limit_address_space(headroom);
        int code = 0;
        try {
            f();
        } catch (const Error& e) {
            std::ofstream(message_file) << e.what();
            code = 1;
        }
        std::_Exit(code);
    }
    int status = 0;
    rusage usage{};
    ::wait4(pid, &status, 0, &usage);
    ChildResult r;
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    const std::uint64_t peak = std::uint64_t(usage.ru_maxrss) * 1024;
    r.peak_added = peak > base ? peak - base : 0;
    std::ifstream in(message_file, std::ios::binary);
    r.message.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return r;
}

}  // namespace librt::testing
