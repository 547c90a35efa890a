// Spot and directional lights (issue 12 item 8) against closed-form irradiance: through
// sample_li, and through DirectLighting on a diffuse floor (radiance = albedo / pi * E).

#include "light_scene_test_util.h"

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>

namespace librt {
namespace {

using testing::irradiance_by_sampling;

/// A scene with only a large diffuse floor of albedo 0.5 at y = 0.
std::uint32_t add_floor(Scene& scene) {
    TriangleMesh mesh;
    mesh.positions = {{-50, 0, -50}, {-50, 0, 50}, {50, 0, 50}, {50, 0, -50}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    return scene.add_mesh(mesh, scene.add_material(Material::diffuse(glm::vec3(0.5f))));
}

/// The radiance DirectLighting sees on the floor at (x, 0, z), from straight above.
glm::vec3 floor_radiance(const Scene& scene, float x, float z, std::uint32_t sample = 0) {
    Ray r;
    r.origin = {x, 1.0f, z};
    r.direction = {0.0f, -1.0f, 0.0f};
    DirectLighting direct;
    Sampler sampler(0, 0, sample, 9);
    return direct.li(scene, r, sampler);
}

TEST(SpotLight, IrradianceMatchesGltfFalloffClosedForm) {
    const SpotLight spot{{0, 2, 0}, {0, -1, 0}, glm::vec3(10.0f), 0.3f, 0.6f};
    Scene scene;
    add_floor(scene);
    scene.add_spot_light(spot);
    scene.commit();
    for (const float x : {0.0f, 0.4f, 0.6f, 0.8f, 1.0f, 1.5f}) {
        // Closed form: E = I f(theta) cos(theta) / d^2 with glTF's falloff
        // f = clamp((cos theta - cos outer) / (cos inner - cos outer), 0, 1)^2.
        const double d2 = double(x) * x + 4.0, cos_t = 2.0 / std::sqrt(d2);
        const double t =
            std::clamp((cos_t - std::cos(0.6)) / (std::cos(0.3) - std::cos(0.6)), 0.0, 1.0);
        const double e = 10.0 * t * t * cos_t / d2;
        EXPECT_NEAR(floor_radiance(scene, x, 0.0f).x, 0.5 / kPi * e, 1e-5 + 1e-4 * e) << x;
    }
    // Power: the falloff integrated over the sphere, by midpoint quadrature in cos(theta).
    double integral = 0.0;
    const int n = 200000;
    for (int i = 0; i < n; ++i) {
        const float c = -1.0f + 2.0f * (float(i) + 0.5f) / float(n);
        integral += double(spot_falloff(spot, c)) * 2.0 / n;
    }
    EXPECT_NEAR(power(spot).x, 2.0 * kPi * 10.0 * integral, 1e-3 * power(spot).x);
}

TEST(SpotLight, RejectsBadAngles) {
    Scene scene;
    EXPECT_THROW(scene.add_spot_light({{0, 2, 0}, {0, -1, 0}, glm::vec3(1.0f), 0.6f, 0.3f}), Error);
    EXPECT_THROW(scene.add_spot_light({{0, 2, 0}, {0, 0, 0}, glm::vec3(1.0f), 0.1f, 0.3f}), Error);
}

TEST(DirectionalLight, DeltaSunIrradianceIsECosine) {
    const glm::vec3 to_sun = glm::normalize(glm::vec3(0.5f, 1.0f, 0.2f));
    Scene scene;
    add_floor(scene);
    scene.add_directional_light({to_sun, glm::vec3(3.0f), 0.0f});
    scene.commit();
    // E = E_perp cos(theta) (Lambert's cosine law), whatever the point.
    for (const float x : {0.0f, 3.0f, -7.0f})
        EXPECT_NEAR(floor_radiance(scene, x, 1.0f).x, 0.5 / kPi * 3.0 * to_sun.y, 1e-5);
}

TEST(DirectionalLight, SoftSunIrradianceIsECosineAndItsDiskIsSeen) {
    // A uniform disk of directions fully above the horizon gives E = L pi sin^2(r) cos(theta)
    // = E_perp cos(theta): the same as the delta sun, now by sampling the cone.
    const glm::vec3 to_sun = glm::normalize(glm::vec3(0.4f, 1.0f, -0.3f));
    const DirectionalLight sun{to_sun, glm::vec3(2.0f), 0.2f};
    const auto e = irradiance_by_sampling(Light{sun, kInvalidId}, glm::vec3(0.0f),
                                          glm::vec3(0, 1, 0), 200000, 3);
    EXPECT_NEAR(e.mean.x, 2.0 * to_sun.y, 5.0 * e.se.x + 1e-6);
    // Rays escaping toward the sun's disk see L = E / (pi sin^2 r); elsewhere nothing.
    EXPECT_NEAR(escaped_radiance(sun, to_sun).x, 2.0 / (kPi * std::pow(std::sin(0.2), 2)), 1e-3);
    EXPECT_EQ(escaped_radiance(sun, glm::vec3(0, 1, 0)).x, 0.0f);
    // And through the renderer: MIS equals brute force on the floor-and-ball scene.
    Scene scene;
    testing::add_floor_and_ball(scene);
    scene.add_directional_light(sun);
    scene.commit();
    testing::expect_mis_equals_brute(scene, testing::top_camera(), 16, 256, "soft sun");
}

}  // namespace
}  // namespace librt
