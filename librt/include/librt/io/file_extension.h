#pragma once

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

// The readers and writers choose a file's format by its extension, case-insensitively
// (image.PNG is a PNG); so do the apps that choose what to write by it.

namespace librt {

/// The extension of `path`, with its dot, in lower case (".png"; "" when there is none).
[[nodiscard]] inline std::string lower_extension(const std::filesystem::path& path) {
    std::string ext = path.extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
    return ext;
}

}  // namespace librt
