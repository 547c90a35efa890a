#pragma once

// The library's one way to read and to write files (private, never installed).
//
// Reading: only regular files are opened. A FIFO, a device, a socket or a directory
// given as an OBJ, MTL, texture or image would block forever (a FIFO with no writer),
// never end (/dev/zero) or fail obscurely; each is refused with a librt::Error naming the
// path and what it is. The file's size is checked against a limit before a byte is read,
// and the read itself stops at the limit (a file that grows while read is refused too).
//
// Writing: AtomicFile makes a file appear complete or not at all. On Linux its data goes
// to an unnamed O_TMPFILE inode in the target's directory, linked in only after fsync: a
// kill (SIGKILL, SIGXFSZ) during the write leaves no name behind. Elsewhere (or where the
// file system has no O_TMPFILE) it writes a temporary of a fixed short name, ".rt-" plus
// 16 hex digits plus ".tmp", so any legal target name (up to NAME_MAX bytes) works, then
// fsyncs and renames it over the target.

#include <cstdint>
#include <filesystem>
#include <functional>
#include <string>
#include <string_view>

namespace librt::detail {

/// The memory a load may take (issue 37): kLoadMemoryPerByteRead times the bytes of the
/// files it reads, plus kLoadMemoryBaseline; more is refused before it is taken. glTF
/// charges a whole load against it, the image loaders (HDR, textures) each image.
inline constexpr std::uint64_t kLoadMemoryPerByteRead = 16;
/// See kLoadMemoryPerByteRead.
inline constexpr std::uint64_t kLoadMemoryBaseline = std::uint64_t{256} << 20u;

/// The memory bound of a load that reads `file_bytes` bytes of files.
[[nodiscard]] constexpr std::uint64_t load_memory_bound(std::uint64_t file_bytes) {
    return kLoadMemoryPerByteRead * file_bytes + kLoadMemoryBaseline;
}

/// What read_regular_file is reading, for its messages and its limit.
struct ReadRequest {
    std::string_view what;        ///< "an OBJ file", "an MTL file", "an image file"...
    std::uint64_t max_bytes;      ///< larger files are refused before reading
    std::string_view raise_hint;  ///< how to raise the limit, appended to that message
    /// Called once with the first bytes (up to 64 KiB, or the whole file if shorter) before
    /// the rest is read: it may throw to refuse a file by its start (a binary file given as
    /// text) without reading gigabytes first.
    std::function<void(std::string_view head)> check_head;
};

/// The whole content of the regular file `path`. Throws librt::Error "path: problem" when
/// it is missing, not a regular file (directory, FIFO, character or block device, socket),
/// unreadable, larger than request.max_bytes, or when check_head throws.
[[nodiscard]] std::string read_regular_file(const std::filesystem::path& path,
                                            const ReadRequest& request);

/// Where a file named by a scene file leads: `dir / name` made canonical (every symlink of
/// the parts that exist followed, "." and ".." resolved), and whether that lies inside
/// dir's own canonical tree. An absolute `name` stands for itself. Scene files may read
/// only inside their tree unless the caller allows more (a downloaded scene must not read
/// /etc/passwd, or a file a symlink beside it points to).
struct TreePath {
    std::filesystem::path path;  ///< the canonical path
    bool inside = false;         ///< it lies in dir's tree
};

/// Resolves `name` against `dir` (see TreePath); throws librt::Error when the file system
/// cannot resolve it.
[[nodiscard]] TreePath resolve_in_tree(const std::filesystem::path& dir,
                                       const std::filesystem::path& name);

/// A file written completely or not at all (see the top of this header). Errors name the
/// target: "cannot write 'path': reason".
class AtomicFile {
public:
    /// Starts a write of `target` (which is not touched until commit()).
    explicit AtomicFile(const std::filesystem::path& target);
    /// Discards the data unless commit() succeeded.
    ~AtomicFile();
    AtomicFile(const AtomicFile&) = delete;
    AtomicFile& operator=(const AtomicFile&) = delete;

    /// Appends bytes.
    void write(std::string_view bytes);
    /// Flushes to disk and gives the data the target's name, replacing any earlier file.
    void commit();

private:
    [[noreturn]] void fail(const std::string& reason);
    void discard() noexcept;

    std::filesystem::path target_;
    std::filesystem::path temp_;  ///< the named temporary, if one was needed
    int fd_ = -1;
    bool unnamed_ = false;  ///< an O_TMPFILE inode, linked in by commit()
};

/// Writes `bytes` to `path` through an AtomicFile.
void write_file_atomically(const std::filesystem::path& path, std::string_view bytes);

}  // namespace librt::detail
