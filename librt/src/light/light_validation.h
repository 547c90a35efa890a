#pragma once

// Private: the parameter checks every light type's validate() shares, so that each error
// names the parameter and its value the same way ("point light position = (x, y, z): must
// be finite").

#include <librt/core/error.h>
#include <librt/core/finite.h>

#include <glm/vec3.hpp>

#include <sstream>

namespace librt::detail {

/// Throws librt::Error "<what> = (x, y, z): <rule>".
[[noreturn]] inline void fail_light_parameter(const char* what, const glm::vec3& v,
                                              const char* rule) {
    std::ostringstream msg;
    msg << what << " = (" << v.x << ", " << v.y << ", " << v.z << "): " << rule;
    throw Error(msg.str());
}

/// Throws librt::Error naming `what` unless every component of v is finite.
inline void require_finite(const char* what, const glm::vec3& v) {
    if (!finite(v)) fail_light_parameter(what, v, "must be finite");
}

/// Throws librt::Error naming `what` unless every component of v is finite and >= 0.
inline void require_finite_non_negative(const char* what, const glm::vec3& v) {
    if (!finite(v) || v.x < 0.0f || v.y < 0.0f || v.z < 0.0f)
        fail_light_parameter(what, v, "must be finite and >= 0");
}

}  // namespace librt::detail
