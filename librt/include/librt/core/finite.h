#pragma once

#include <glm/vec2.hpp>
#include <glm/vec3.hpp>

#include <cmath>

namespace librt {

/// True when every component of `v` is finite (neither NaN nor infinite): the one check
/// that validation of positions, directions, normals, uvs and radiance goes through.
template <glm::length_t L, typename T, glm::qualifier Q>
[[nodiscard]] bool finite(const glm::vec<L, T, Q>& v) {
    for (glm::length_t i = 0; i < L; ++i)
        if (!std::isfinite(v[i])) return false;
    return true;
}

}  // namespace librt
