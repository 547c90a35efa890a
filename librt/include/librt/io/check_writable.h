#pragma once

#include <librt/export.h>

#include <filesystem>

// Whether a file can be written at a path, asked before the work that produces it: an
// output that cannot be written (a read-only file system, a directory the user may not
// write, /proc or /sys, a missing directory, a file used as a directory) is found before a
// render runs, not after it, when the render would be lost.

namespace librt {

/// Creates and removes a temporary file in `path`'s directory, the way librt's writers
/// start every write (on Linux an unnamed O_TMPFILE inode, which never has a name; elsewhere
/// `.rt-<16 hex digits>.tmp`, removed at once). `path` itself is not touched. Throws
/// librt::Error "cannot write 'path': reason" (the system's reason, strerror) when that
/// fails; leaves nothing behind either way.
LIBRT_API void check_writable(const std::filesystem::path& path);

}  // namespace librt
