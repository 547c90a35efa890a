// Builds a BVH over a triangle mesh, casts a few rays and prints what they hit, checking
// each answer against the brute-force TriangleList. The mesh is an OBJ given on the
// command line, or else a torus built by hand.
//   bvh_only [mesh.obj]

#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>
#include <librt/geometry/mesh.h>
#include <librt/obj/obj.h>
#include <librt/version.h>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
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

int main(int argc, char** argv) {
    std::printf("librt %s (headers %s)\n", librt::library_version_string(),
                librt::version_string());
    try {
        const librt::TriangleMesh mesh =
            argc > 1 ? librt::load_obj(argv[1]) : make_torus(2.0f, 0.5f, 96, 48);
        const librt::TriangleBvh bvh(mesh, librt::BvhBuilder::Sah);
        const librt::TriangleList brute_force(mesh);
        const librt::BBox box = bvh.bounds();
        const librt::BvhStats stats = bvh.stats();
        std::printf("%s: %zu triangles, BVH of %zu nodes, depth %u, %zu bytes\n",
                    argc > 1 ? argv[1] : "torus", bvh.triangle_count(), stats.node_count,
                    stats.depth, stats.bytes);
        std::printf("bounds: (%.3f, %.3f, %.3f) .. (%.3f, %.3f, %.3f)\n", box.lo.x, box.lo.y,
                    box.lo.z, box.hi.x, box.hi.y, box.hi.z);

        // From a point above and in front, aim at points of the mesh's middle plane (for
        // the torus: the middle of the tube, the hole, the outer rim, the far side) and
        // at points outside it.
        const glm::vec3 c = box.center();
        const glm::vec3 half = 0.5f * box.diagonal();
        const float r = std::max(half.x, std::max(half.y, half.z));
        const glm::vec3 eye = c + r * glm::vec3(0.0f, 1.2f, 2.4f);
        const glm::vec3 offsets[] = {
            {0.0f, 0.0f, 0.8f},   {0.0f, 0.0f, 0.0f}, {0.98f, 0.0f, 0.0f},
            {-0.8f, 0.0f, -0.8f}, {2.0f, 0.0f, 0.0f}, {0.0f, -1.6f, 0.0f},
        };
        int mismatches = 0;
        for (const glm::vec3& offset : offsets) {
            const glm::vec3 target = c + r * offset;
            librt::Ray ray;
            ray.origin = eye;
            ray.direction = glm::normalize(target - eye);
            const librt::PrimitiveHit hit = bvh.intersect(ray);
            const librt::PrimitiveHit expected = brute_force.intersect(ray);
            std::printf("ray to (%6.2f, %6.2f, %6.2f): ", target.x, target.y, target.z);
            if (hit.valid()) {
                const glm::vec3 p = ray.at(hit.t);
                std::printf("hit triangle %u at t = %.4f, point (%.3f, %.3f, %.3f)",
                            hit.primitive_id, hit.t, p.x, p.y, p.z);
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
    } catch (const librt::Error& e) {
        std::fprintf(stderr, "bvh_only: %s\n", e.what());
        return 2;
    }
}
