// File access and messages of the glTF loader: read_regular_file (the one place bytes
// come from), tinygltf's routed file callbacks, and Context.

#include "gltf/gltf_internal.h"
#include "io/file_io.h"

#include <librt/core/error.h>
#include <librt/core/untrusted_text.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstring>
#include <string>

namespace librt::gltf_detail {

namespace fs = std::filesystem;

std::string read_regular_file(const fs::path& path, std::uint64_t max_bytes) {
    const std::string name = path.string();
    struct stat info {};
    if (::stat(name.c_str(), &info) != 0) {
        if (errno == ENOENT || errno == ENOTDIR) throw Error(name + ": no such file");
        throw Error(name + ": cannot access: " + std::strerror(errno));
    }
    if (S_ISDIR(info.st_mode)) throw Error(name + ": is a directory, not a file");
    if (!S_ISREG(info.st_mode)) {
        // A FIFO or device could block the open or never end: refuse before opening.
        throw Error(name + ": not a regular file (a FIFO, device or socket)");
    }
    // O_NONBLOCK: should the path have become a FIFO since the stat, open does not block.
    const int fd = ::open(name.c_str(), O_RDONLY | O_CLOEXEC | O_NONBLOCK);
    if (fd < 0) throw Error(name + ": cannot open for reading: " + std::strerror(errno));
    struct Closer {
        int fd;
        ~Closer() { ::close(fd); }
    } closer{fd};
    if (::fstat(fd, &info) != 0 || !S_ISREG(info.st_mode))
        throw Error(name + ": not a regular file (a FIFO, device or socket)");
    const auto size = static_cast<std::uint64_t>(info.st_size);
    if (size > max_bytes) {
        throw Error(name + ": " + std::to_string(size) + " bytes, more than the limit of " +
                    std::to_string(max_bytes));
    }
    std::string bytes(static_cast<std::size_t>(size), '\0');
    std::size_t done = 0;
    while (done < bytes.size()) {
        const ssize_t got = ::read(fd, bytes.data() + done, bytes.size() - done);
        if (got < 0 && errno == EINTR) continue;
        if (got < 0) throw Error(name + ": read error: " + std::strerror(errno));
        if (got == 0) throw Error(name + ": file shrank while being read");
        done += static_cast<std::size_t>(got);
    }
    return bytes;
}

void Context::fail(std::string_view json_path, std::string_view what) const {
    std::string message = file_ + ": ";
    if (!json_path.empty()) message.append(json_path).append(": ");
    message.append(what);
    throw Error(message);
}

void Context::warn(std::string_view json_path, std::string_view what) const {
    std::string message = file_ + ": ";
    if (!json_path.empty()) message.append(json_path).append(": ");
    message.append(what);
    warnings_->push_back(printable(message, kMaxErrorBytes));
}

void Context::spend(std::uint64_t bytes, std::string_view json_path) {
    if (bytes > budget_) {
        fail(json_path, "decoding needs " + std::to_string(bytes) +
                            " more bytes than the loader allows for this file (" +
                            std::to_string(budget_) +
                            " left; memory is limited to a multiple of the bytes read)");
    }
    budget_ -= bytes;
}

std::string indexed(std::string_view array, std::size_t index) {
    return std::string(array) + "[" + std::to_string(index) + "]";
}

void check_index(const Context& ctx, std::string_view json_path, int index, std::size_t count,
                 std::string_view what) {
    if (index < 0 || static_cast<std::size_t>(index) >= count) {
        ctx.fail(json_path, std::string(what) + " " + std::to_string(index) + " does not exist (" +
                                std::to_string(count) + " in the file)");
    }
}

std::string decode_uri(std::string_view uri) {
    // As tinygltf resolves external URIs (so the pre-pass checks the file it will read):
    // '+' is a space, '%' takes the next two characters as hex digits (others count 0).
    auto hex = [](char c) -> int {
        if (c >= '0' && c <= '9') return c - '0';
        if (c >= 'a' && c <= 'f') return c - 'a' + 10;
        if (c >= 'A' && c <= 'F') return c - 'A' + 10;
        return 0;
    };
    std::string out;
    out.reserve(uri.size());
    for (std::size_t i = 0; i < uri.size(); ++i) {
        if (uri[i] == '+') {
            out.push_back(' ');
        } else if (uri[i] == '%' && uri.size() > i + 2) {
            out.push_back(static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2])));
            i += 2;
        } else {
            out.push_back(uri[i]);
        }
    }
    return out;
}

std::string not_regular_reason(const std::string& path) {
    struct stat info {};
    if (::stat(path.c_str(), &info) != 0) {
        if (errno == ENOENT || errno == ENOTDIR) return "no such file";
        return std::string("cannot access: ") + std::strerror(errno);
    }
    if (S_ISREG(info.st_mode)) return {};
    if (S_ISDIR(info.st_mode)) return "a directory, not a file";
    if (S_ISCHR(info.st_mode)) return "a character device, not a file";
    if (S_ISBLK(info.st_mode)) return "a block device, not a file";
    if (S_ISFIFO(info.st_mode)) return "a FIFO, not a file";
    if (S_ISSOCK(info.st_mode)) return "a socket, not a file";
    return "not a regular file";
}

std::string file_in_scene_tree(const std::string& base_dir, std::string_view uri,
                               bool allow_outside, const std::string& json_path,
                               const Context& ctx) {
    std::string decoded = decode_uri(uri);
    // RFC 3986 section 3.1: a scheme is a letter, then letters, digits, '+', '-' or '.',
    // then ':', before any '/'. Only a file: URI names a local file; others never do.
    std::size_t scheme_end = 0;
    if (!decoded.empty() && std::isalpha(static_cast<unsigned char>(decoded[0]))) {
        std::size_t k = 1;
        while (k < decoded.size() && (std::isalnum(static_cast<unsigned char>(decoded[k])) ||
                                      decoded[k] == '+' || decoded[k] == '-' || decoded[k] == '.'))
            ++k;
        if (k < decoded.size() && decoded[k] == ':') scheme_end = k + 1;
    }
    const std::string lift =
        " (a scene file reads only files in its own directory tree; "
        "GltfLoadOptions::allow_outside_files, rt_render --allow-outside-files, lifts this "
        "for a file you trust)";
    if (scheme_end != 0) {
        const std::string scheme = decoded.substr(0, scheme_end);
        bool is_file = scheme.size() == 5;
        for (std::size_t k = 0; is_file && k < 4; ++k)
            is_file = std::tolower(static_cast<unsigned char>(scheme[k])) == "file"[k];
        if (!is_file)
            ctx.fail(json_path, quote_untrusted(uri) +
                                    ": only relative paths and data: URIs are read, not " +
                                    quote_untrusted(scheme) + " URIs");
        if (!allow_outside) ctx.fail(json_path, quote_untrusted(uri) + ": a file: URI" + lift);
        decoded.erase(0, scheme_end);
        // file://host/path: only an empty host (or localhost) names this machine.
        if (decoded.rfind("//", 0) == 0) {
            const std::size_t slash = decoded.find('/', 2);
            const std::string host =
                decoded.substr(2, slash == std::string::npos ? std::string::npos : slash - 2);
            if (!host.empty() && host != "localhost")
                ctx.fail(json_path, quote_untrusted(uri) + ": a file on another host");
            decoded.erase(0, slash == std::string::npos ? decoded.size() : slash);
        }
    }
    if (decoded.empty()) ctx.fail(json_path, "an empty uri names no file");
    if (decoded.find('\0') != std::string::npos)
        ctx.fail(json_path, quote_untrusted(uri) + ": a NUL byte in a file name");
    const fs::path named(decoded);
    if (named.is_absolute() && !allow_outside)
        ctx.fail(json_path, quote_untrusted(uri) + ": an absolute path" + lift);
    detail::TreePath file;
    try {
        file = detail::resolve_in_tree(base_dir, named);
    } catch (const Error& e) {
        ctx.fail(json_path, e.what());
    }
    if (!file.inside && !allow_outside) {
        ctx.fail(json_path, quote_untrusted(uri) + ": leads outside the scene's directory" + lift);
    }
    return file.path.string();
}

namespace {

bool no_file_exists(const std::string&, void*) { return false; }
std::string no_expand(const std::string& path, void*) { return path; }  // no ~ or $VAR
bool no_read(std::vector<unsigned char>*, std::string* err, const std::string&, void*) {
    if (err) *err += "tinygltf reads no file in librt";
    return false;
}
bool no_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "the glTF loader never writes files";
    return false;
}

}  // namespace

tinygltf::FsCallbacks no_file_access() {
    tinygltf::FsCallbacks callbacks{};
    callbacks.FileExists = &no_file_exists;
    callbacks.ExpandFilePath = &no_expand;
    callbacks.ReadWholeFile = &no_read;
    callbacks.WriteWholeFile = &no_write;
    callbacks.user_data = nullptr;
    return callbacks;
}

bool ignore_image(tinygltf::Image* image, int, std::string*, std::string*, int, int,
                  const unsigned char*, int, void*) {
    image->as_is = true;
    return true;
}

}  // namespace librt::gltf_detail
