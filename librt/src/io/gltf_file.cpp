// File access and messages of the glTF loader: read_regular_file (the one place bytes
// come from), tinygltf's routed file callbacks, and Context.

#include "io/gltf_internal.h"

#include <librt/core/error.h>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
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
    warnings_->push_back(std::move(message));
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

std::string resolve_uri(const std::string& base_dir, std::string_view uri) {
    std::string decoded = decode_uri(uri);
    if (base_dir.empty()) return decoded;
    return base_dir.back() == '/' ? base_dir + decoded : base_dir + "/" + decoded;
}

namespace {

bool routed_file_exists(const std::string& path, void* user_data) {
    const auto* routing = static_cast<const FsRouting*>(user_data);
    // tinygltf also tries the working directory; only the glTF's own directory counts.
    if (path.compare(0, routing->base_dir.size(), routing->base_dir) != 0) return false;
    struct stat info {};
    return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

std::string routed_expand(const std::string& path, void*) { return path; }  // no ~ or $VAR

bool routed_read(std::vector<unsigned char>* out, std::string* err, const std::string& path,
                 void* user_data) {
    auto* routing = static_cast<FsRouting*>(user_data);
    try {
        const std::string bytes = read_regular_file(path, routing->max_bytes);
        std::size_t keep = bytes.size();
        if (const auto it = routing->truncate_to.find(path); it != routing->truncate_to.end())
            keep = std::min<std::size_t>(keep, static_cast<std::size_t>(it->second));
        out->assign(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(keep));
        return true;
    } catch (const Error& e) {
        routing->failures[path] = e.what();
        if (err) *err += e.what();
        return false;
    }
}

bool routed_write(std::string* err, const std::string&, const std::vector<unsigned char>&, void*) {
    if (err) *err += "the glTF loader never writes files";
    return false;
}

}  // namespace

tinygltf::FsCallbacks FsRouting::callbacks() {
    tinygltf::FsCallbacks callbacks{};
    callbacks.FileExists = &routed_file_exists;
    callbacks.ExpandFilePath = &routed_expand;
    callbacks.ReadWholeFile = &routed_read;
    callbacks.WriteWholeFile = &routed_write;
    callbacks.user_data = this;
    return callbacks;
}

bool keep_encoded_image(tinygltf::Image* image, int, std::string*, std::string*, int, int,
                        const unsigned char* bytes, int size, void*) {
    // Images in a buffer view are read from the (range-checked) buffer later; only bytes
    // tinygltf loaded from a file or data: URI are kept here.
    if (image->bufferView < 0 && bytes != nullptr && size > 0)
        image->image.assign(bytes, bytes + size);
    image->as_is = true;
    return true;
}

}  // namespace librt::gltf_detail
