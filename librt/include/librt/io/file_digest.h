#pragma once

#include <librt/export.h>

#include <cstdint>
#include <filesystem>
#include <string>

// A file's bytes reduced to a 64-bit FNV-1a digest (core/fnv1a.h) and its size: what the
// ranks of an MPI job compare to be sure they read the same scene (mpi/same_job.h).

namespace librt {

/// A file's content in 16 bytes: its FNV-1a digest and its size.
struct FileDigest {
    std::uint64_t fnv1a64 = 0;  ///< core/fnv1a.h over every byte of the file
    std::uint64_t bytes = 0;    ///< the file's size
};

/// Reads `path` whole, in blocks of 1 MiB: FNV-1a takes its bytes one at a time, about
/// 0.3 GB/s on this project's shared 2-core machine (docs/distributed.md). Throws
/// librt::Error naming the file when it cannot be opened or read.
[[nodiscard]] LIBRT_API FileDigest file_digest(const std::filesystem::path& path);

/// "fnv1a64 <16 hex digits>, <size> bytes": how the digest is shown in messages.
[[nodiscard]] LIBRT_API std::string to_string(const FileDigest& digest);

}  // namespace librt
