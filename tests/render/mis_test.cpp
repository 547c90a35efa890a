// Multiple importance sampling in PathTracer: on the report's room with its sphere light it
// estimates the same image as the brute-force reference and as next-event estimation
// alone (PathTracerSettings::mis = false), over the whole image and 4 x 4 blocks, and at
// equal samples its variance is no worse than next-event estimation's. Tolerances come
// from the sample variance (integrator_test_util.h).

#include "integrator_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace librt {
namespace {

using testing::add_room;
using testing::Pinhole;
using testing::region;
using testing::RegionEstimate;
using testing::render_stats;
using testing::room_camera;
using testing::StatImage;

// |a - b| <= k * sqrt(se_a^2 + se_b^2) per channel.
void expect_same(const RegionEstimate& a, const RegionEstimate& b, double k,
                 const std::string& where) {
    for (int c = 0; c < 3; ++c) {
        const double tol = k * std::sqrt(a.se2[c] + b.se2[c]);
        EXPECT_LE(std::fabs(a.mean[c] - b.mean[c]), tol)
            << where << " channel " << c << ": " << a.mean[c] << " vs " << b.mean[c] << " (se "
            << std::sqrt(a.se2[c]) << ", " << std::sqrt(b.se2[c]) << ")";
    }
}

void expect_same_image(const StatImage& a, const StatImage& b, const std::string& what) {
    const int w = a.width, h = a.height;
    expect_same(region(a, 0, 0, w, h), region(b, 0, 0, w, h), 5.0, what + ", whole image");
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx)
            expect_same(region(a, bx * w / 4, by * h / 4, (bx + 1) * w / 4, (by + 1) * h / 4),
                        region(b, bx * w / 4, by * h / 4, (bx + 1) * w / 4, (by + 1) * h / 4), 5.0,
                        what + ", block " + std::to_string(bx) + "," + std::to_string(by));
}

void build_soft_shadow_room(Scene& scene) {
    add_room(scene);
    scene.add_sphere_light({{{-10, 20, 40}, 10}, glm::vec3(50.0f)});
    scene.commit();
}

TEST(Mis, AgreesWithBruteForceAndWithLightSamplingAlone) {
    Scene scene;
    build_soft_shadow_room(scene);
    const Pinhole cam = room_camera(24);
    PathTracer mis(PathTracerSettings{5, false});
    PathTracerSettings nee_settings{5, false};
    nee_settings.mis = false;
    PathTracer nee(nee_settings);
    BruteForcePathTracer brute(PathTracerSettings{5, false});
    ASSERT_TRUE(mis.settings().mis);
    const StatImage a = render_stats(scene, mis, cam, 96, 21);
    const StatImage b = render_stats(scene, nee, cam, 96, 22);
    const StatImage c = render_stats(scene, brute, cam, 600, 23);
    EXPECT_EQ(mis.nonfinite_count() + nee.nonfinite_count() + brute.nonfinite_count(), 0u);
    expect_same_image(a, b, "MIS vs light sampling alone");
    expect_same_image(a, c, "MIS vs brute force");
    // Power: the whole-image differences are resolved to 3%.
    const RegionEstimate wa = region(a, 0, 0, 24, 24), wb = region(b, 0, 0, 24, 24);
    for (int ch = 0; ch < 3; ++ch)
        EXPECT_LT(std::sqrt(wa.se2[ch] + wb.se2[ch]), 0.03 * wb.mean[ch]) << ch;
}

// Sum over pixels of the per-pixel sample variance (all channels) of n samples each, with
// the standard error of that sum from the samples' fourth central moments:
// Var(s^2) ~ (m4 - s^4 (n - 3) / (n - 1)) / n per pixel (the variance of a sample
// variance), pixels independent.
struct VarianceSum {
    double total = 0.0;
    double se = 0.0;
};

VarianceSum variance_sum(const Scene& scene, Integrator& integrator, const Pinhole& cam, int n,
                         std::uint64_t seed) {
    integrator.preprocess(scene);
    VarianceSum v;
    double var_of_total = 0.0;
    std::vector<glm::dvec3> samples(static_cast<std::size_t>(n));
    for (int y = 0; y < cam.height; ++y)
        for (int x = 0; x < cam.width; ++x) {
            const Ray ray = cam.ray(x, y);
            for (int s = 0; s < n; ++s) {
                Sampler sampler(std::uint32_t(x), std::uint32_t(y), std::uint32_t(s), seed);
                samples[std::size_t(s)] = glm::dvec3(integrator.li(scene, ray, sampler));
            }
            for (int c = 0; c < 3; ++c) {
                double mean = 0.0;
                for (const glm::dvec3& l : samples) mean += l[c];
                mean /= n;
                double m2 = 0.0, m4 = 0.0;
                for (const glm::dvec3& l : samples) {
                    const double d2 = (l[c] - mean) * (l[c] - mean);
                    m2 += d2;
                    m4 += d2 * d2;
                }
                const double s2 = m2 / (n - 1);
                m4 /= n;
                v.total += s2;
                var_of_total += std::max(0.0, (m4 - s2 * s2 * (n - 3.0) / (n - 1.0)) / n);
            }
        }
    v.se = std::sqrt(var_of_total);
    return v;
}

TEST(Mis, VarianceNoWorseThanLightSamplingAloneOnSoftShadows) {
    Scene scene;
    build_soft_shadow_room(scene);
    const Pinhole cam = room_camera(32);
    PathTracer mis(PathTracerSettings{5, false});
    PathTracerSettings nee_settings{5, false};
    nee_settings.mis = false;
    PathTracer nee(nee_settings);
    const int n = 64;
    const VarianceSum vm = variance_sum(scene, mis, cam, n, 31);
    const VarianceSum vn = variance_sum(scene, nee, cam, n, 32);
    std::printf(
        "summed pixel variance at %d spp: MIS %.6g (se %.3g), NEE only %.6g (se %.3g), "
        "ratio %.4f\n",
        n, vm.total, vm.se, vn.total, vn.se, vm.total / vn.total);
    // The comparison has power: each sum is known to better than 10%.
    EXPECT_LT(vm.se, 0.1 * vm.total);
    EXPECT_LT(vn.se, 0.1 * vn.total);
    // No worse: MIS's sum exceeds NEE's by at most 3 standard errors of the difference.
    EXPECT_LE(vm.total - vn.total, 3.0 * std::sqrt(vm.se * vm.se + vn.se * vn.se));
}

}  // namespace
}  // namespace librt
