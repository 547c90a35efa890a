#include "io/file_io.h"

#include <librt/core/error.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <random>

namespace librt::detail {

namespace fs = std::filesystem;

namespace {

// Built by appending: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
std::string quoted(const fs::path& path) {
    std::string out(1, '\'');
    out += path.string();
    out += '\'';
    return out;
}

/// What a file that is not regular is, for the message.
const char* kind_of(mode_t mode) {
    if (S_ISDIR(mode)) return "a directory";
    if (S_ISFIFO(mode)) return "a FIFO (named pipe)";
    if (S_ISCHR(mode)) return "a character device";
    if (S_ISBLK(mode)) return "a block device";
    if (S_ISSOCK(mode)) return "a socket";
    return "not a regular file";
}

/// Closes a descriptor on every path out of a scope.
struct FdGuard {
    int fd;
    ~FdGuard() {
        if (fd >= 0) ::close(fd);
    }
};

/// Reads up to `count` bytes at `out`, retrying after signals; returns the bytes read
/// (fewer only at the end of the file), or -1 with errno set.
ssize_t read_fully(int fd, char* out, std::size_t count) {
    std::size_t got = 0;
    while (got < count) {
        const ssize_t n = ::read(fd, out + got, count - got);
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) return -1;
        if (n == 0) break;
        got += static_cast<std::size_t>(n);
    }
    return static_cast<ssize_t>(got);
}

/// 16 hex digits no other writer (thread or process) picks at the same time.
std::string unique_hex() {
    static const std::uint64_t process_bits = [] {
        std::random_device device;
        return (std::uint64_t{device()} << 32u) ^ std::uint64_t{device()};
    }();
    static std::atomic<std::uint64_t> counter{0};
    // splitmix64 of the process bits plus a counter: distinct per call, well mixed.
    std::uint64_t h = process_bits + 0x9E3779B97F4A7C15ull * (counter.fetch_add(1) + 1);
    h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;
    h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
    h ^= h >> 31;
    char buffer[17];
    std::snprintf(buffer, sizeof buffer, "%016llx", static_cast<unsigned long long>(h));
    return buffer;
}

/// Makes a completed rename or link durable (best effort: some file systems refuse).
void sync_directory(const fs::path& dir) {
    const int fd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd < 0) return;
    (void)::fsync(fd);
    ::close(fd);
}

}  // namespace

std::string read_regular_file(const fs::path& path, const ReadRequest& request) {
    const std::string name = path.string();
    // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer, forever.
    const int fd = ::open(path.c_str(), O_RDONLY | O_NONBLOCK | O_CLOEXEC);
    if (fd < 0) {
        const int e = errno;
        if (e == ENOENT) throw Error(name + ": no such file");
        throw Error(name + ": cannot open for reading: " + std::strerror(e));
    }
    const FdGuard guard{fd};
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        throw Error(name + ": cannot access: " + std::strerror(errno));
    }
    if (!S_ISREG(st.st_mode)) {
        throw Error(name + ": is " + kind_of(st.st_mode) + ", not " + std::string(request.what));
    }
    const auto size = static_cast<std::uint64_t>(st.st_size);
    auto too_big = [&](const std::string& size_text) {
        std::string message = name + ": " + size_text + " bytes, more than the limit of " +
                              std::to_string(request.max_bytes) + " bytes for " +
                              std::string(request.what);
        if (!request.raise_hint.empty()) message += " (" + std::string(request.raise_hint) + ")";
        return Error(message);
    };
    if (size > request.max_bytes) throw too_big(std::to_string(size));

    std::string data;
    constexpr std::size_t kHead = std::size_t{1} << 16;
    data.resize(static_cast<std::size_t>(std::min<std::uint64_t>(size, kHead)));
    ssize_t got = read_fully(fd, data.data(), data.size());
    if (got < 0) throw Error(name + ": read error: " + std::strerror(errno));
    data.resize(static_cast<std::size_t>(got));
    if (request.check_head) request.check_head(data);
    if (static_cast<std::size_t>(got) < kHead && static_cast<std::uint64_t>(got) < size) {
        return data;  // shrank while read: what is there
    }
    // The rest, in blocks, never past the limit (the file may have grown since fstat).
    data.reserve(static_cast<std::size_t>(size));
    for (;;) {
        const std::size_t old = data.size();
        const std::size_t block = std::max<std::size_t>(kHead, size > old ? size - old : 0);
        const std::uint64_t room =
            request.max_bytes + 1 - std::min<std::uint64_t>(old, request.max_bytes + 1);
        const auto want = static_cast<std::size_t>(std::min<std::uint64_t>(block, room));
        if (want == 0) throw too_big("more than " + std::to_string(request.max_bytes));
        data.resize(old + want);
        got = read_fully(fd, data.data() + old, want);
        if (got < 0) throw Error(name + ": read error: " + std::strerror(errno));
        data.resize(old + static_cast<std::size_t>(got));
        if (data.size() > request.max_bytes) {
            throw too_big("more than " + std::to_string(request.max_bytes));
        }
        if (static_cast<std::size_t>(got) < want) return data;
    }
}

AtomicFile::AtomicFile(const fs::path& target) : target_(target) {
    if (target.filename().empty()) fail("no file name");
    const fs::path dir = target.parent_path();
    const std::string dir_name = dir.empty() ? "." : dir.string();
#ifdef O_TMPFILE
    // The unnamed inode is linked in through /proc/self/fd (linkat's AT_EMPTY_PATH needs a
    // capability): without /proc, use the named temporary.
    static const bool have_proc_fd = ::access("/proc/self/fd", X_OK) == 0;
    if (have_proc_fd) fd_ = ::open(dir_name.c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
    if (fd_ >= 0) {
        unnamed_ = true;
        return;
    }
    // EISDIR / EOPNOTSUPP: the kernel or file system has no O_TMPFILE; others (ENOENT,
    // EACCES) would fail the named temporary just the same and are reported by it.
#endif
    for (int attempt = 0; attempt < 16; ++attempt) {
        temp_ = dir / (".rt-" + unique_hex() + ".tmp");
        // O_EXCL: never reuse an existing file of that name.
        fd_ = ::open(temp_.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd_ >= 0) return;
        if (errno != EEXIST) break;
    }
    const int e = errno;
    temp_.clear();
    fail(std::strerror(e));
}

AtomicFile::~AtomicFile() { discard(); }

void AtomicFile::discard() noexcept {
    if (fd_ >= 0) ::close(fd_);
    fd_ = -1;
    if (!temp_.empty()) ::unlink(temp_.c_str());
    temp_.clear();
}

void AtomicFile::fail(const std::string& reason) {
    discard();
    throw Error("cannot write " + quoted(target_) + ": " + reason);
}

void AtomicFile::write(std::string_view bytes) {
    if (fd_ < 0) fail("already closed");
    while (!bytes.empty()) {
        const ssize_t n = ::write(fd_, bytes.data(), bytes.size());
        if (n < 0 && errno == EINTR) continue;
        if (n < 0) fail(std::strerror(errno));
        bytes.remove_prefix(static_cast<std::size_t>(n));
    }
}

void AtomicFile::commit() {
    if (fd_ < 0) fail("already closed");
    if (::fsync(fd_) != 0) fail(std::strerror(errno));
    const fs::path dir = target_.parent_path();
    if (unnamed_) {
        // The inode gets its first name only now, complete and on disk. linkat cannot
        // replace an existing file: then link to a short temporary and rename that over
        // the target (the temporary exists only between two system calls, and complete).
        const std::string proc = "/proc/self/fd/" + std::to_string(fd_);
        if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, target_.c_str(), AT_SYMLINK_FOLLOW) == 0) {
            ::close(fd_);
            fd_ = -1;
            sync_directory(dir);
            return;
        }
        if (errno != EEXIST) fail(std::strerror(errno));
        for (int attempt = 0; attempt < 16 && temp_.empty(); ++attempt) {
            const fs::path candidate = dir / (".rt-" + unique_hex() + ".tmp");
            if (::linkat(AT_FDCWD, proc.c_str(), AT_FDCWD, candidate.c_str(), AT_SYMLINK_FOLLOW) ==
                0) {
                temp_ = candidate;
            } else if (errno != EEXIST) {
                fail(std::strerror(errno));
            }
        }
        if (temp_.empty()) fail("no free temporary name");
    }
    if (::close(fd_) != 0) {
        fd_ = -1;
        fail(std::strerror(errno));
    }
    fd_ = -1;
    if (::rename(temp_.c_str(), target_.c_str()) != 0) fail(std::strerror(errno));
    temp_.clear();
    sync_directory(dir);
}

void write_file_atomically(const fs::path& path, std::string_view bytes) {
    AtomicFile file(path);
    file.write(bytes);
    file.commit();
}

TreePath resolve_in_tree(const fs::path& dir, const fs::path& name) {
    std::error_code ec;
    const fs::path root = fs::weakly_canonical(dir.empty() ? fs::path(".") : dir, ec);
    if (ec) throw Error(quoted(dir) + ": cannot resolve: " + ec.message());
    TreePath out;
    out.path = fs::weakly_canonical(name.is_absolute() ? name : root / name, ec);
    if (ec) throw Error(quoted(name) + ": cannot resolve: " + ec.message());
    const fs::path rel = out.path.lexically_relative(root);
    out.inside = !rel.empty() && *rel.begin() != "..";
    return out;
}

}  // namespace librt::detail
