// End to end through Scene::shade and the path tracers: a brushed white conductor (F = 1,
// anisotropic) sphere inside a uniform emitter. The sphere is convex, so every reflected
// ray meets the emitter and a pixel sees Le E(wo), E the anisotropic GGX single-scattering
// albedo at wo expressed in the lobe's frame at the hit: x along the sphere's dP/du turned
// by the rotation toward n x dP/du. Both the MIS and the brute-force path tracer must
// match the test's own quadrature within 5 standard errors; with the frame turned the
// wrong way (or not at all) the pixels off the symmetry axes would not.

#include "render/anisotropic_ggx_test_util.h"
#include "render/integrator_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/material/material.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>

namespace librt {
namespace {

TEST(AnisotropicFurnace, BrushedSphereRendersLeTimesTheAnisotropicAlbedo) {
    // alpha_b = 0.2^2 = 0.04, alpha_t = mix(0.04, 1, 1) = 1: at grazing incidence the
    // albedo depends strongly on wo's azimuth about the brushing direction.
    const float roughness = 0.2f, strength = 1.0f, rotation = 0.6f;
    const double ab = double(roughness) * roughness;
    const double at = ab + (1.0 - ab) * double(strength) * strength;
    Material m = Material::conductor(glm::vec3(1.0f), glm::vec3(1000.0f), roughness);
    m.anisotropy = strength;
    m.anisotropy_rotation = rotation;
    Scene scene;
    scene.add_sphere({{0, 0, 0}, 1.0f}, scene.add_material(m));
    scene.add_sphere({{0, 0, 0}, 50.0f}, scene.add_material(Material::emissive(glm::vec3(1.0f))));
    scene.commit();
    testing::Pinhole cam;
    // The sphere fills the middle of a 7 x 7 image; the outer pixels meet it near its rim
    // (grazing wo) or miss it and see the emitter.
    cam.eye = {0.0f, 0.0f, 4.0f};
    cam.fov_degrees = 32.0f;
    cam.width = cam.height = 7;
    int grazing = 0;
    PathTracer path({8});
    BruteForcePathTracer brute({8});
    for (Integrator* integrator :
         {static_cast<Integrator*>(&path), static_cast<Integrator*>(&brute)}) {
        const testing::StatImage img = testing::render_stats(scene, *integrator, cam, 4000, 7);
        for (int y = 0; y < cam.height; ++y)
            for (int x = 0; x < cam.width; ++x) {
                const Ray ray = cam.ray(x, y);
                const glm::dvec3 o(ray.origin), d(ray.direction);
                const double b = glm::dot(o, d), disc = b * b - (glm::dot(o, o) - 1.0);
                const testing::PixelStats& s = img.at(x, y);
                if (disc <= 0.0) {
                    EXPECT_NEAR(s.mean().x, 1.0, 1e-5) << "the emitter, pixel " << x << "," << y;
                    continue;
                }
                const glm::dvec3 n = glm::normalize(o + (-b - std::sqrt(disc)) * d);
                // dP/du of the sphere's (u = azimuth about +y) parameterisation, turned.
                const glm::dvec3 t = glm::normalize(glm::dvec3(-n.z, 0.0, n.x));
                const glm::dvec3 dir =
                    std::cos(double(rotation)) * t + std::sin(double(rotation)) * glm::cross(n, t);
                const glm::dvec3 wo = -d;
                const glm::dvec3 wo_lobe(glm::dot(wo, dir), glm::dot(wo, glm::cross(n, dir)),
                                         glm::dot(wo, n));
                const double expected = testing::ref_anisotropic_albedo(wo_lobe, at, ab);
                grazing += wo_lobe.z < 0.5 ? 1 : 0;
                const double se = std::sqrt(s.variance().x / s.n);
                EXPECT_LT(se, 0.01) << "the test has power";
                EXPECT_NEAR(s.mean().x, expected, 5.0 * se + 2e-4) << "pixel " << x << "," << y;
            }
    }
    EXPECT_GE(grazing, 8) << "pixels at grazing incidence, where the azimuth matters";
}

}  // namespace
}  // namespace librt
