#pragma once

// Ray sets shared by the BVH tests and benchmarks (header-only, deterministic).

#include <librt/geometry/bbox.h>
#include <librt/geometry/ray.h>

#include <glm/geometric.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/trigonometric.hpp>

#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

namespace librt::testing {

/// Incoherent rays: origins uniform on a sphere of 1.5x the box's half-diagonal
/// around its centre, each aimed at a uniform random point inside the box.
inline std::vector<Ray> incoherent_rays(const BBox& box, std::size_t count, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    const glm::vec3 c = box.center();
    const float radius = 1.5f * 0.5f * glm::length(box.diagonal());
    std::vector<Ray> rays(count);
    for (Ray& r : rays) {
        // Uniform point on the sphere: z uniform in [-1, 1], azimuth uniform.
        const float z = 1.0f - 2.0f * U(rng);
        const float s = std::sqrt(std::max(0.0f, 1.0f - z * z));
        const float phi = glm::two_pi<float>() * U(rng);
        r.origin = c + radius * glm::vec3(s * std::cos(phi), s * std::sin(phi), z);
        const glm::vec3 target = box.lo + box.diagonal() * glm::vec3(U(rng), U(rng), U(rng));
        r.direction = glm::normalize(target - r.origin);
    }
    return rays;
}

/// Primary rays of a width x height pinhole camera (vertical fov in degrees) placed on
/// the +z side of the box at a distance that frames it, looking at its centre.
inline std::vector<Ray> primary_rays(const BBox& box, int width, int height, float fov_degrees) {
    const glm::vec3 c = box.center();
    const float radius = 0.5f * glm::length(box.diagonal());
    const float half = std::tan(glm::radians(fov_degrees) * 0.5f);
    const glm::vec3 eye = c + glm::vec3(0.0f, 0.0f, radius / half * 1.1f);
    std::vector<Ray> rays;
    rays.reserve(std::size_t(width) * std::size_t(height));
    for (int i = 0; i < height; ++i)
        for (int j = 0; j < width; ++j) {
            const float x = (2.0f * (float(j) + 0.5f) / float(width) - 1.0f) * half * float(width) /
                            float(height);
            const float y = (1.0f - 2.0f * (float(i) + 0.5f) / float(height)) * half;
            Ray r;
            r.origin = eye;
            r.direction = glm::normalize(glm::vec3(x, y, -1.0f));
            rays.push_back(r);
        }
    return rays;
}

}  // namespace librt::testing
