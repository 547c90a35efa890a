#pragma once

// Triangle sets shared by the BVH tests (header-only, deterministic).

#include <librt/geometry/mesh.h>
#include <librt/geometry/triangle.h>

#include <glm/vec3.hpp>

#include <cstdint>
#include <random>
#include <vector>

namespace librt::testing {

/// A random soup of small triangles in the unit cube, plus a few large ones across it
/// (every 97th): overlapping boxes of very different sizes, hard for a builder.
inline std::vector<Triangle> random_soup(std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    std::vector<Triangle> tris(count);
    for (std::size_t i = 0; i < count; ++i) {
        const glm::vec3 c{U(rng), U(rng), U(rng)};
        const float s = (i % 97 == 0) ? 0.5f : 0.03f;
        auto corner = [&] {
            return c + s * glm::vec3(U(rng) - 0.5f, U(rng) - 0.5f, U(rng) - 0.5f);
        };
        tris[i] = {corner(), corner(), corner()};
    }
    return tris;
}

/// A mesh's triangles as a flat list.
inline std::vector<Triangle> triangles_of(const TriangleMesh& mesh) {
    std::vector<Triangle> tris(mesh.triangle_count());
    for (std::size_t i = 0; i < tris.size(); ++i) tris[i] = mesh.triangle(i);
    return tris;
}

}  // namespace librt::testing
