// Environment light (issue 12 item 9): sampled directions follow pdf_li (chi-square over
// equal-solid-angle bins), a one-bright-pixel environment is found, and the MIS path
// tracer equals the brute-force one under a constant environment and under sky.hdr.

#include "light_scene_test_util.h"

#include <librt/core/error.h>
#include <librt/io/hdr_image.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <test_support.h>

#include <cmath>
#include <vector>

namespace librt {
namespace {

/// A rotation about axis by angle, as a 3x3 matrix.
glm::mat3 rotation(float angle, const glm::vec3& axis) {
    return glm::mat3(glm::rotate(glm::mat4(1.0f), angle, glm::normalize(axis)));
}

/// A 32 x 16 image with smooth variation and a bright patch.
EnvironmentImage test_image() {
    EnvironmentImage im{32, 16, {}};
    for (int y = 0; y < 16; ++y)
        for (int x = 0; x < 32; ++x) {
            const float v =
                0.2f + 0.1f * float((x * 7 + y * 3) % 5) + (x == 5 && y == 4 ? 30.0f : 0.0f);
            im.pixels.push_back({v, 0.5f * v, 0.1f + 0.01f * float(y)});
        }
    return im;
}

TEST(EnvironmentLight, SampledDirectionsFollowPdfChiSquare) {
    const EnvironmentLight env =
        EnvironmentLight::from_image(test_image(), rotation(0.7f, {1, 2, 0.5f}), 1.0f);
    const Light light{env, kInvalidId};
    // Bins equal in solid angle in the WORLD frame: cos(theta) in 12 bands, phi in 24.
    const int nc = 12, np = 24, n = 400000;
    std::vector<double> observed(std::size_t(nc * np), 0.0), expected(observed.size(), 0.0);
    Pcg32 rng(42, 1);
    int mismatches = 0;  // float rounding may move a sample on a pixel edge across it
    for (int i = 0; i < n; ++i) {
        const LightLiSample s =
            sample_li(light, glm::vec3(0.0f), {rng.next_float(), rng.next_float()});
        ASSERT_TRUE(s.valid());
        if (!(std::fabs(pdf_li(light, glm::vec3(0.0f), s.wi) - s.pdf) <= 1e-3f * s.pdf))
            ++mismatches;
        const int c = std::min(nc - 1, int((s.wi.y + 1.0f) * 0.5f * float(nc)));
        float phi = std::atan2(s.wi.z, s.wi.x);
        if (phi < 0.0f) phi += 2.0f * kPi;
        const int p = std::min(np - 1, int(phi / (2.0f * kPi) * float(np)));
        observed[std::size_t(c * np + p)] += 1.0;
    }
    EXPECT_LE(mismatches, n / 10000) << "pdf_li disagrees with sample_li";
    // Expected counts: n times pdf_li integrated over each bin (midpoint rule, 16 x 16).
    const int sub = 16;
    double total = 0.0;
    for (int c = 0; c < nc; ++c)
        for (int p = 0; p < np; ++p) {
            double sum = 0.0;
            for (int i = 0; i < sub; ++i)
                for (int j = 0; j < sub; ++j) {
                    const double z = -1.0 + 2.0 * (c + (i + 0.5) / sub) / nc;
                    const double phi = 2.0 * kPi * (p + (j + 0.5) / sub) / np;
                    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
                    const glm::vec3 w(float(r * std::cos(phi)), float(z), float(r * std::sin(phi)));
                    sum += pdf_li(light, glm::vec3(0.0f), w);
                }
            // Each bin has solid angle 4 pi / (nc np).
            expected[std::size_t(c * np + p)] = sum / (sub * sub) * 4.0 * kPi / (nc * np);
            total += expected[std::size_t(c * np + p)];
        }
    EXPECT_NEAR(total, 1.0, 0.02) << "pdf_li integrates to 1 over the sphere";
    double chi2 = 0.0;
    int dof = -1;
    for (std::size_t b = 0; b < observed.size(); ++b) {
        const double e = expected[b] / total * n;
        if (e < 5.0) continue;  // too few to test: pooled out
        chi2 += (observed[b] - e) * (observed[b] - e) / e;
        ++dof;
    }
    // Wilson-Hilferty bound for the chi-square upper 1e-4 quantile (z = 3.72).
    const double k = dof, z = 3.72;
    const double bound = k * std::pow(1.0 - 2.0 / (9.0 * k) + z * std::sqrt(2.0 / (9.0 * k)), 3.0);
    EXPECT_LT(chi2, bound) << "dof " << dof;
}

TEST(EnvironmentLight, DeltaLikePixelIsFound) {
    EnvironmentImage im{64, 32, std::vector<glm::vec3>(64 * 32, glm::vec3(0.0f))};
    const int px = 40, py = 9;  // above the horizon: theta < pi/2
    im.pixels[std::size_t(py * 64 + px)] = glm::vec3(1000.0f);
    const EnvironmentLight env = EnvironmentLight::from_image(im);
    const Light light{env, kInvalidId};
    // Every sample lands in that pixel and sees its radiance.
    Pcg32 rng(3, 1);
    for (int i = 0; i < 1000; ++i) {
        const LightLiSample s =
            sample_li(light, glm::vec3(0.0f), {rng.next_float(), rng.next_float()});
        ASSERT_TRUE(s.valid());
        EXPECT_EQ(s.radiance.x, 1000.0f);
        EXPECT_EQ(escaped_radiance(env, s.wi).x, 1000.0f);
    }
    // Irradiance on an upward normal equals the pixel's closed form: L dphi
    // int cos(theta) sin(theta) dtheta = L dphi (sin^2 t1 - sin^2 t0) / 2.
    const double t0 = kPi * py / 32.0, t1 = kPi * (py + 1) / 32.0;
    const double expected =
        1000.0 * (2.0 * kPi / 64.0) * 0.5 * (std::pow(std::sin(t1), 2) - std::pow(std::sin(t0), 2));
    const auto e =
        testing::irradiance_by_sampling(light, glm::vec3(0.0f), glm::vec3(0, 1, 0), 100000, 8);
    EXPECT_NEAR(e.mean.x, expected, 5.0 * e.se.x + 1e-3 * expected);
}

TEST(EnvironmentLight, ConstantMisEqualsBruteForceAndHidesFromCamera) {
    Scene scene;
    testing::add_floor_and_ball(scene);
    scene.add_environment_light(EnvironmentLight::constant({0.6f, 0.8f, 1.0f}));
    scene.commit();
    testing::expect_mis_equals_brute(scene, testing::side_camera(), 16, 64, "constant sky");

    Scene hidden;
    testing::add_floor_and_ball(hidden);
    hidden.add_environment_light(EnvironmentLight::constant({0.6f, 0.8f, 1.0f}), false);
    hidden.commit();
    testing::Pinhole up = testing::side_camera();
    up.width = up.height = 1;
    up.forward = {0, 1, 0};
    up.up = {0, 0, -1};
    PathTracer pt;
    Sampler sampler(0, 0, 0, 1);
    EXPECT_EQ(pt.li(hidden, up.ray(0, 0), sampler).x, 0.0f) << "the camera sees black sky";
    EXPECT_GT(pt.li(scene, up.ray(0, 0), sampler).x, 0.5f);
}

TEST(EnvironmentLight, SkyHdrMisEqualsBruteForce) {
    LIBRT_REQUIRE_DATA_FILE(path, "sky.hdr");
    const EnvironmentImage sky = load_hdr_image(path);
    EXPECT_EQ(sky.width, 2 * sky.height);
    Scene scene;
    testing::add_floor_and_ball(scene);
    scene.add_environment_light(EnvironmentLight::from_image(sky, rotation(0.5f, {0, 1, 0}), 0.5f));
    scene.commit();
    testing::expect_mis_equals_brute(scene, testing::side_camera(), 32, 512, "sky.hdr");
}

TEST(EnvironmentLight, RejectsBadInput) {
    EXPECT_THROW((void)EnvironmentLight::from_image({2, 2, {glm::vec3(1.0f)}}), Error);
    EXPECT_THROW((void)EnvironmentLight::constant({-1, 0, 0}), Error);
    EXPECT_THROW((void)load_hdr_image("/nonexistent/sky.hdr"), Error);
    EnvironmentImage nan{1, 1, {glm::vec3(std::nanf(""))}};
    EXPECT_THROW((void)EnvironmentLight::from_image(nan), Error);
}

}  // namespace
}  // namespace librt
