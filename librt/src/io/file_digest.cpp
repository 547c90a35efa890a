#include <librt/core/error.h>
#include <librt/core/fnv1a.h>
#include <librt/io/file_digest.h>

#include <cerrno>
#include <cinttypes>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

namespace librt {

FileDigest file_digest(const std::filesystem::path& path) {
    struct Close {
        void operator()(std::FILE* f) const { std::fclose(f); }
    };
    const std::unique_ptr<std::FILE, Close> file(std::fopen(path.c_str(), "rb"));
    if (!file) throw Error(path.string() + ": cannot open the file (" + std::strerror(errno) + ")");
    std::vector<std::byte> block(std::size_t{1} << 20);
    FileDigest d;
    d.fnv1a64 = kFnv1a64Offset;
    while (true) {
        const std::size_t n = std::fread(block.data(), 1, block.size(), file.get());
        d.fnv1a64 = fnv1a64(std::span(block.data(), n), d.fnv1a64);
        d.bytes += n;
        if (n < block.size()) break;
    }
    if (std::ferror(file.get()) != 0) throw Error(path.string() + ": cannot read the file");
    return d;
}

FileDigest digest_of(std::string_view bytes) { return {fnv1a64(bytes), bytes.size()}; }

std::string to_string(const FileDigest& digest) {
    char text[64];
    std::snprintf(text, sizeof text, "fnv1a64 %016" PRIx64 ", %" PRIu64 " bytes", digest.fnv1a64,
                  digest.bytes);
    return text;
}

}  // namespace librt
