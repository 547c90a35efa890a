#pragma once

#include <librt/core/untrusted_text.h>
#include <librt/export.h>

#include <stdexcept>
#include <string>

namespace librt {

/// Most bytes of an Error's message (a longer one is cut, with "…").
inline constexpr std::size_t kMaxErrorBytes = 4096;

/// The one exception type librt throws: bad input (a file, a parameter) or a
/// resource it cannot get. The message names what was wrong, e.g.
/// "bunny.obj:12: face index 0 is out of range" or "spp = -1: must be >= 1".
/// It is always one printable line: control characters are escaped (printable()), so text
/// taken from a file can never reach a terminal raw, and it holds at most kMaxErrorBytes.
class LIBRT_API Error : public std::runtime_error {
public:
    /// An error with the given message (made printable), returned by what().
    explicit Error(const std::string& message)
        : std::runtime_error(printable(message, kMaxErrorBytes)) {}
};

}  // namespace librt
