#pragma once

#include <librt/export.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

// A file's bytes reduced to a 64-bit FNV-1a digest (core/fnv1a.h) and its size: what the
// ranks of an MPI job compare to be sure they read the same scene (mpi/same_job.h), the
// scene file and every file it names (LoadedScene::files_read).

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

/// The digest of bytes already in memory: a loader's, over the file it has just read, so
/// that no file is read a second time for its digest. Equals file_digest of a file holding
/// exactly `bytes`.
[[nodiscard]] LIBRT_API FileDigest digest_of(std::string_view bytes);

/// A file a scene loader read, with the digest of the bytes it used.
struct FileRead {
    std::filesystem::path path;  ///< as the loader opened it (see LoadedScene::files_read)
    FileDigest digest;           ///< of the bytes read
};

/// "fnv1a64 <16 hex digits>, <size> bytes": how the digest is shown in messages.
[[nodiscard]] LIBRT_API std::string to_string(const FileDigest& digest);

}  // namespace librt
