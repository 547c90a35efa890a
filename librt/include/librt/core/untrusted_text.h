#pragma once

#include <librt/export.h>

#include <cstddef>
#include <limits>
#include <string>
#include <string_view>

// Text that came from a file (names, tokens, URIs) on its way into a message. A scene file
// is untrusted input: printed as is, its escape sequences could restyle the terminal, and
// CR/LF could forge lines of output; one enormous token would make an enormous message.

namespace librt {

/// `text` made safe to print: control characters (C0, DEL, and C1 written in UTF-8) and
/// bytes that are not valid UTF-8 become escapes such as "\x1b", "\n", "\r", "\t" or
/// "\u009b"; valid UTF-8 is kept. Longer than max_bytes (counted in the output), it is cut
/// at a character boundary and "…" is appended.
[[nodiscard]] LIBRT_API std::string printable(
    std::string_view text, std::size_t max_bytes = std::numeric_limits<std::size_t>::max());

/// Most bytes of a value quoted by quote_untrusted, before the "…".
inline constexpr std::size_t kMaxQuotedBytes = 80;

/// printable(text, kMaxQuotedBytes) between single quotes: how every value taken from a
/// file is quoted in librt's errors and warnings.
[[nodiscard]] LIBRT_API std::string quote_untrusted(std::string_view text);

}  // namespace librt
