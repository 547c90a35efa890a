// Builds a BVH over a procedural torus, casts a few rays and prints what they hit,
// checking each answer against the brute-force TriangleList.

#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/mesh.h>
#include <librt/version.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <numbers>

namespace {

/// A torus around the y axis: `rings` segments around the axis, `sides` around the tube.
librt::TriangleMesh make_torus(float major_radius, float minor_radius, std::uint32_t rings,
                               std::uint32_t sides) {
    constexpr float two_pi = 2.0f * std::numbers::pi_v<float>;
    librt::TriangleMesh mesh;
    for (std::uint32_t i = 0; i < rings; ++i) {
        const float phi = two_pi * static_cast<float>(i) / static_cast<float>(rings);
        for (std::uint32_t j = 0; j < sides; ++j) {
            const float theta = two_pi * static_cast<float>(j) / static_cast<float>(sides);
            const float r = major_radius + minor_radius * std::cos(theta);
            mesh.positions.emplace_back(r * std::cos(phi), minor_radius * std::sin(theta),
                                        r * std::sin(phi));
        }
    }
    for (std::uint32_t i = 0; i < rings; ++i) {
        for (std::uint32_t j = 0; j < sides; ++j) {
            const std::uint32_t a = i * sides + j;
            const std::uint32_t b = ((i + 1) % rings) * sides + j;
            const std::uint32_t c = ((i + 1) % rings) * sides + (j + 1) % sides;
            const std::uint32_t d = i * sides + (j + 1) % sides;
            mesh.triangles.emplace_back(a, b, c);
            mesh.triangles.emplace_back(a, c, d);
        }
    }
    return mesh;
}

}  // namespace

int main() {
    std::printf("librt %s (headers %s)\n", librt::library_version_string(),
                librt::version_string());

    const librt::TriangleMesh torus = make_torus(2.0f, 0.5f, 96, 48);
    const librt::TriangleBvh bvh(torus, librt::BvhBuilder::Sah);
    const librt::TriangleList brute_force(torus);
    const librt::BBox box = bvh.bounds();
    std::printf("torus: %zu triangles, BVH of %zu nodes, depth %u, %zu bytes\n",
                bvh.triangle_count(), bvh.bvh().nodes.size(), bvh.bvh().depth, bvh.memory_bytes());
    std::printf("bounds: (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f)\n", box.lo.x, box.lo.y, box.lo.z,
                box.hi.x, box.hi.y, box.hi.z);

    // From a point above and in front, aim at points of the torus's plane: the middle of
    // the tube, the hole in the middle, the outer rim, and far outside.
    const glm::vec3 eye{0.0f, 3.0f, 6.0f};
    const glm::vec3 targets[] = {
        {0.0f, 0.0f, 2.0f},   {0.0f, 0.0f, 0.0f}, {2.45f, 0.0f, 0.0f},
        {-2.0f, 0.0f, -2.0f}, {5.0f, 0.0f, 0.0f}, {0.0f, -4.0f, 0.0f},
    };
    int mismatches = 0;
    for (const glm::vec3& target : targets) {
        librt::Ray ray;
        ray.origin = eye;
        ray.direction = glm::normalize(target - eye);
        const librt::PrimitiveHit hit = bvh.intersect(ray);
        const librt::PrimitiveHit expected = brute_force.intersect(ray);
        std::printf("ray to (%5.2f, %5.2f, %5.2f): ", target.x, target.y, target.z);
        if (hit.valid()) {
            const glm::vec3 p = ray.at(hit.t);
            std::printf("hit triangle %u at t = %.4f, point (%.3f, %.3f, %.3f)", hit.primitive_id,
                        hit.t, p.x, p.y, p.z);
        } else {
            std::printf("miss");
        }
        std::printf(", occluded: %s\n", bvh.occluded(ray) ? "yes" : "no");
        if (hit.valid() != expected.valid() || (hit.valid() && hit.t != expected.t)) {
            std::printf("  MISMATCH: the brute-force scan says %s\n",
                        expected.valid() ? "hit" : "miss");
            ++mismatches;
        }
    }
    return mismatches == 0 ? 0 : 1;
}
