#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

// FNV-1a with 64 bits (Fowler, Noll and Vo; offset basis and prime as published at
// http://www.isthe.com/chongo/tech/comp/fnv/): a digest that tells apart inputs differing
// by mistake, such as the ranks of an MPI job given different scene files (mpi/same_job.h).
// Not a cryptographic hash, on purpose: anyone can build two inputs with one FNV digest, but
// the check guards against mistakes, not attackers, and FNV-1a is a few lines, needs no
// library and is the same on every platform.

namespace librt {

inline constexpr std::uint64_t kFnv1a64Offset = 0xcbf29ce484222325ULL;
inline constexpr std::uint64_t kFnv1a64Prime = 0x00000100000001b3ULL;

/// The digest `h` continued over `bytes`: start from kFnv1a64Offset; a digest continued over
/// the pieces of an input in order is the digest of the whole.
[[nodiscard]] constexpr std::uint64_t fnv1a64(std::span<const std::byte> bytes,
                                              std::uint64_t h = kFnv1a64Offset) {
    for (const std::byte b : bytes) h = (h ^ std::to_integer<std::uint64_t>(b)) * kFnv1a64Prime;
    return h;
}

/// fnv1a64 of the characters of `text`.
[[nodiscard]] constexpr std::uint64_t fnv1a64(std::string_view text,
                                              std::uint64_t h = kFnv1a64Offset) {
    for (const char c : text) h = (h ^ static_cast<unsigned char>(c)) * kFnv1a64Prime;
    return h;
}

}  // namespace librt
