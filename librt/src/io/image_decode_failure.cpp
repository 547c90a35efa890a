#include "io/image_decode_failure.h"

#include <stb/stb_image.h>

namespace librt::detail {

std::string image_decode_failure(std::string_view bytes) {
    const char* raw = stbi_failure_reason();
    const std::string_view reason = raw != nullptr ? raw : "";
    const bool png = bytes.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8);
    const bool jpeg = bytes.size() >= 3 && static_cast<unsigned char>(bytes[0]) == 0xFF &&
                      static_cast<unsigned char>(bytes[1]) == 0xD8 &&
                      static_cast<unsigned char>(bytes[2]) == 0xFF;
    if (!png && !jpeg) return reason.empty() ? "cannot decode" : std::string(reason);
    std::string out = png ? "a corrupt or truncated PNG" : "a corrupt or truncated JPEG";
    // Complaints that are not this format's decoder speaking about this file.
    const bool other =
        reason.empty() || reason == "unknown image type" || (jpeg && reason == "bad png sig");
    if (!other) {
        out += " (";
        out += reason;
        out += ')';
    }
    return out;
}

}  // namespace librt::detail
