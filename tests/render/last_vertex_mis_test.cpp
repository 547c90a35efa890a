// The last scattering event of a path on a glossy lobe keeps multiple importance
// sampling. Light sampling alone there divides a peaked f by a light pdf that knows
// nothing of the peak: on cornell_pbr.glb one sample through the (roughness 0) glass cube
// read 2800 times the panel's radiance. With MIS (power heuristic) and VNDF sampling the
// bound is exact: a BSDF sample's weight f cos / pdf_b = F G2 / G1 <= 1 gives f cos <= pdf_b,
// so the light sample adds at most L pdf_l pdf_b / (pdf_l^2 + pdf_b^2) <= L / 2 and the
// BSDF sample at most L: no sample exceeds 1.5 L. The estimate stays unbiased (brute force).

#include <librt/integrator/integrators.h>
#include <librt/light/quad_light.h>
#include <librt/material/material.h>
#include <librt/sampling/sampler.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace librt {
namespace {

constexpr float kRadiance = 10.0f;

/// A near-mirror floor (white rough conductor, roughness 0.05: GGX alpha 0.0025) under a
/// small one-sided quad light that the camera ray's mirror direction hits.
void build_glossy_floor(Scene& scene) {
    TriangleMesh floor;
    floor.positions = {{-5, 0, -5}, {-5, 0, 5}, {5, 0, 5}, {5, 0, -5}};
    floor.triangles = {{0, 1, 2}, {0, 2, 3}};
    const auto metal =
        scene.add_material(Material::conductor_artist(glm::vec3(1.0f), glm::vec3(1.0f), 0.05f));
    scene.add_mesh(floor, metal);
    // Centred at (2, 2, 0), facing down (edge0 x edge1 = -y).
    (void)scene.add_quad_light(
        QuadLight{{1.9f, 2.0f, -0.1f}, {0.2f, 0, 0}, {0, 0, 0.2f}, glm::vec3(kRadiance), false});
    scene.commit();
}

struct Estimate {
    double mean = 0.0, se = 0.0, max = 0.0;
};

Estimate estimate(const Scene& scene, const Integrator& integrator, int n, std::uint64_t seed) {
    Ray ray;
    ray.origin = {-1.0f, 1.0f, 0.0f};
    ray.direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
    double sum = 0.0, sum2 = 0.0, max = 0.0;
    for (int i = 0; i < n; ++i) {
        Sampler sampler(SamplerKind::Independent, 0, 0, std::uint32_t(i), seed);
        const double v = double(integrator.li(scene, ray, sampler).g);
        sum += v;
        sum2 += v * v;
        max = std::max(max, v);
    }
    const double mean = sum / n;
    return {mean, std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1)), max};
}

TEST(LastVertexMis, GlossyLastVertexSampleIsBoundedAndUnbiased) {
    Scene scene;
    build_glossy_floor(scene);
    PathTracerSettings settings;
    settings.max_depth = 1;  // the floor is the path's last scattering event
    settings.russian_roulette = false;
    constexpr int n = 40000;
    const Estimate mis = estimate(scene, PathTracer(settings), n, 7);
    const Estimate brute = estimate(scene, BruteForcePathTracer(settings), n, 8);
    // The mirror direction is inside the light and the lobe is narrower than the light, so
    // the floor reflects nearly L: a non-trivial estimate to compare.
    EXPECT_GT(brute.mean, 0.5 * kRadiance);
    EXPECT_LE(mis.max, 1.5 * kRadiance * (1.0 + 1e-4)) << "a light sample without MIS";
    EXPECT_NEAR(mis.mean, brute.mean, 5.0 * std::sqrt(mis.se * mis.se + brute.se * brute.se));
}

}  // namespace
}  // namespace librt
