#pragma once

// Why stb_image could not read an image, in words that do not mislead (private).

#include <string>
#include <string_view>

namespace librt::detail {

/// Why stb_image could not read the encoded image `bytes`, to call right after
/// stbi_info_from_memory or stbi_load_from_memory failed on them. A PNG or JPEG (known by
/// its signature) is "a corrupt or truncated PNG" / "... JPEG", with stb's reason in
/// parentheses when that reason is the decoder's own: stb tries the formats in turn and
/// keeps the last complaint, so for a truncated JPEG it may hold the PNG test's
/// "bad png sig" (that test runs first, and the JPEG decoder can fail without a word) or
/// "unknown image type" (every format refused it). Another format: stb's reason as is.
[[nodiscard]] std::string image_decode_failure(std::string_view bytes);

}  // namespace librt::detail
