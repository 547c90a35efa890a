// printable() and quote_untrusted(): messages never carry a file's control characters.

#include <librt/core/untrusted_text.h>

#include <cstdint>

namespace librt {

namespace {

/// Length of the valid UTF-8 sequence at text[i] (RFC 3629: no overlongs, no surrogates,
/// at most U+10FFFF), or 0 when it is not one; *code gets its code point.
std::size_t utf8_length(std::string_view text, std::size_t i, std::uint32_t* code) {
    const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
    const unsigned char b0 = byte(i);
    std::size_t n = 0;
    std::uint32_t c = 0, min = 0;
    if (b0 < 0x80) {
        *code = b0;
        return 1;
    }
    if ((b0 & 0xE0) == 0xC0)
        n = 2, c = b0 & 0x1Fu, min = 0x80;
    else if ((b0 & 0xF0) == 0xE0)
        n = 3, c = b0 & 0x0Fu, min = 0x800;
    else if ((b0 & 0xF8) == 0xF0)
        n = 4, c = b0 & 0x07u, min = 0x10000;
    else
        return 0;
    if (i + n > text.size()) return 0;
    for (std::size_t k = 1; k < n; ++k) {
        if ((byte(i + k) & 0xC0) != 0x80) return 0;
        c = (c << 6u) | (byte(i + k) & 0x3Fu);
    }
    if (c < min || c > 0x10FFFF || (c >= 0xD800 && c <= 0xDFFF)) return 0;
    *code = c;
    return n;
}

}  // namespace

std::string printable(std::string_view text, std::size_t max_bytes) {
    static constexpr char kHex[] = "0123456789abcdef";
    static constexpr std::string_view kEllipsis = "\xE2\x80\xA6";  // U+2026
    std::string out;
    out.reserve(text.size() < max_bytes ? text.size() : max_bytes);
    for (std::size_t i = 0; i < text.size();) {
        std::uint32_t code = 0;
        const std::size_t n = utf8_length(text, i, &code);
        std::string piece;
        if (n == 0) {  // not UTF-8: the byte itself, escaped
            const auto b = static_cast<unsigned char>(text[i]);
            piece = {'\\', 'x', kHex[b >> 4u], kHex[b & 15u]};
        } else if (code == '\n') {
            piece = "\\n";
        } else if (code == '\r') {
            piece = "\\r";
        } else if (code == '\t') {
            piece = "\\t";
        } else if (code < 0x20 || code == 0x7F) {
            piece = {'\\', 'x', kHex[code >> 4u], kHex[code & 15u]};
        } else if (code >= 0x80 && code < 0xA0) {  // C1 controls (CSI is U+009B)
            piece = {'\\', 'u', '0', '0', kHex[code >> 4u], kHex[code & 15u]};
        } else {
            piece.assign(text.substr(i, n));
        }
        if (out.size() + piece.size() > max_bytes) {
            out.append(kEllipsis);
            return out;
        }
        out += piece;
        i += n == 0 ? 1 : n;
    }
    return out;
}

std::string quote_untrusted(std::string_view text) {
    std::string out(1, '\'');
    out += printable(text, kMaxQuotedBytes);
    out += '\'';
    return out;
}

}  // namespace librt
