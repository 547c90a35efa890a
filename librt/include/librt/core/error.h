#pragma once

#include <librt/export.h>

#include <stdexcept>
#include <string>

namespace librt {

/// The one exception type librt throws: bad input (a file, a parameter) or a
/// resource it cannot get. The message names what was wrong, e.g.
/// "bunny.obj:12: face index 0 is out of range" or "spp = -1: must be >= 1".
class LIBRT_API Error : public std::runtime_error {
public:
    /// An error with the given message, returned by what().
    explicit Error(const std::string& message) : std::runtime_error(message) {}
};

}  // namespace librt
