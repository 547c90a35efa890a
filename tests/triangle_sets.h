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

/// An n x n grid of unit squares at z = 0, two triangles each (a, b, c and a, c, d): shared
/// edges and vertices on integer coordinates, where rays along the lattice test
/// watertightness.
inline std::vector<Triangle> unit_grid(int n) {
    std::vector<Triangle> tris;
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            const glm::vec3 a{float(i), float(j), 0}, b{float(i + 1), float(j), 0},
                c{float(i + 1), float(j + 1), 0}, d{float(i), float(j + 1), 0};
            tris.push_back({a, b, c});
            tris.push_back({a, c, d});
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
