// The glTF 2.0 metallic-roughness BSDF against the specification's formulas evaluated here
// by hand; the rough dielectric's albedo against a quadrature of its eval over microfacet
// normals, and its roughness-0 limit against the smooth Dielectric; and the furnace: a
// sphere of each reflecting BSDF inside a uniform emitter renders Le times its directional
// albedo (computed here by quadrature), with the MIS and the brute-force path tracers.

#include "render/integrator_test_util.h"
#include "render/microfacet_test_util.h"
#include "sampling/sanitizer_scale.h"

#include <librt/integrator/integrators.h>
#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace librt {
namespace {

using testing::flat_point;
using testing::local_dir;

constexpr double kPi = std::numbers::pi;

/// The glTF 2.0 metallic-roughness BRDF of the spec's Appendix B, in double: D_GGX,
/// V_GGX (height-correlated form of the spec's implementation notes), conductor_fresnel
/// and fresnel_mix with f0 = 0.04. `diffuse_only`/`specular_only` split it for quadrature.
glm::dvec3 gltf_brdf(const glm::dvec3& v, const glm::dvec3& l, const glm::dvec3& c, double metallic,
                     double roughness, int part = 3) {
    const glm::dvec3 h = glm::normalize(l + v);
    const double nl = l.z, nv = v.z, nh = h.z, vh = std::fabs(glm::dot(v, h));
    const double a = roughness * roughness, a2 = a * a;
    const double t = nh * nh * (a2 - 1.0) + 1.0;
    const double d = nh > 0.0 ? a2 / (kPi * t * t) : 0.0;
    const double vis = 0.5 / (nl * std::sqrt(nv * nv * (1.0 - a2) + a2) +
                              nv * std::sqrt(nl * nl * (1.0 - a2) + a2));
    const double s5 = std::pow(1.0 - vh, 5.0);
    const glm::dvec3 metal_f = c + (glm::dvec3(1.0) - c) * s5;
    const double fr = 0.04 + 0.96 * s5;
    const glm::dvec3 diffuse = (1.0 - fr) * c / kPi;
    const glm::dvec3 spec = glm::dvec3(fr * d * vis);
    glm::dvec3 out(0.0);
    if (part & 1) out += (1.0 - metallic) * diffuse;
    if (part & 2) out += (1.0 - metallic) * spec + metallic * metal_f * d * vis;
    return out;
}

// At 12 random (wo, wi, base colour, metallic, roughness) the library's eval equals the
// spec's formula; reflection only (no transmission), roughness above the alpha clamp.
TEST(GltfBrdf, EqualsSpecFormulas) {
    Pcg32 rng(12, 12);
    for (int i = 0; i < 12; ++i) {
        const glm::vec3 wo = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 wi = local_dir(0.05 + 0.95 * rng.next_float(), 6.283 * rng.next_float());
        const glm::vec3 c(rng.next_float(), rng.next_float(), rng.next_float());
        const float metallic = i == 0 ? 0.0f : i == 1 ? 1.0f : rng.next_float();
        const float roughness = 0.1f + 0.9f * rng.next_float();
        const Material m = Material::metallic_roughness(c, metallic, roughness);
        const glm::vec3 f = eval(m, flat_point(), wo, wi);
        const glm::dvec3 expected =
            gltf_brdf(glm::dvec3(wo), glm::dvec3(wi), glm::dvec3(c), metallic, roughness);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(f[k], expected[k], 1e-4 * expected[k] + 1e-7) << "point " << i;
    }
    // Thin transmission: (1 - metallic) (1 - Fr) transmission c D V at the mirrored wi.
    const glm::vec3 wo = local_dir(0.7, 0.2), wi = local_dir(-0.6, 2.0);
    const glm::vec3 c(0.9f, 0.5f, 0.3f);
    const Material t = Material::metallic_roughness(c, 0.25f, 0.5f, 1.5f, 0.6f);
    const glm::dvec3 wr(wi.x, wi.y, -wi.z);
    // spec part with metallic 0 is Fr D V; Fr D V (1 - Fr) / Fr needs Fr: recompute it.
    const glm::dvec3 h = glm::normalize(wr + glm::dvec3(wo));
    const double fr = 0.04 + 0.96 * std::pow(1.0 - glm::dot(glm::dvec3(wo), h), 5.0);
    const double dv = gltf_brdf(glm::dvec3(wo), wr, glm::dvec3(1.0), 0.0, 0.5, 2).x / fr;
    const glm::vec3 ft = eval(t, flat_point(), wo, wi);
    for (int k = 0; k < 3; ++k) {
        const double expected = 0.75 * (1.0 - fr) * 0.6 * c[k] * dv;
        EXPECT_NEAR(ft[k], expected, 1e-4 * expected);
    }
}

// Rough glass: the sampled mean weight (reflection + transmission albedo) equals the
// integral of eval |cos_i| computed over microfacet normals with Walter et al.'s
// Jacobians (reflection 4 |wo.h|, refraction (wi.h + wo.h / eta)^2 / |wi.h|), from both
// sides of the surface, and is <= 1.
TEST(GltfBrdf, RoughDielectricAlbedoMatchesQuadrature) {
    const int n = librt::testing::scaled_samples(200'000);  // 8 cases: 1.6e6 in all
    for (const float r : {0.3f, 0.8f})
        for (const bool front : {true, false})
            for (const double co : {0.9, 0.4}) {
                const Material m = Material::rough_dielectric(1.5f, r);
                const ShadingPoint p = flat_point(front);
                const glm::dvec3 wo(local_dir(co, 0.4));
                const double eta = front ? 1.5 : 1.0 / 1.5;
                const double expected =
                    testing::integrate_over_normals(r * r, [&](const glm::dvec3& h) {
                        const double oh = glm::dot(wo, h);
                        if (oh <= 0.0) return 0.0;
                        double sum = 0.0;
                        const glm::dvec3 wr = 2.0 * oh * h - wo;
                        if (wr.z > 0.0)
                            sum += eval(m, p, glm::vec3(wo), glm::vec3(wr)).x * wr.z * 4.0 * oh;
                        // Snell about h: wt = -wo / eta + (oh / eta - cos_t) h.
                        const double s2 = (1.0 - oh * oh) / (eta * eta);
                        if (s2 < 1.0) {
                            const glm::dvec3 wt = -wo / eta + (oh / eta - std::sqrt(1.0 - s2)) * h;
                            const double th = glm::dot(wt, h), den = th + oh / eta;
                            if (wt.z < 0.0)
                                sum += eval(m, p, glm::vec3(wo), glm::vec3(glm::normalize(wt))).x *
                                       -wt.z * den * den / std::fabs(th);
                        }
                        return sum;
                    });
                Pcg32 rng(9, 9);
                double sum = 0.0, sum2 = 0.0;
                for (int i = 0; i < n; ++i) {
                    const BsdfSample s =
                        sample(m, p, glm::vec3(wo), rng.next_float(), rng.next_vec2());
                    const double w = s.valid() ? s.weight.x : 0.0;
                    sum += w;
                    sum2 += w * w;
                }
                const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
                EXPECT_NEAR(mean, expected, 5.0 * se + 1e-3)
                    << "r " << r << (front ? " outside" : " inside") << " cos " << co;
                EXPECT_LE(mean, 1.0 + 5.0 * se);
            }
}

// Roughness 0 is today's smooth glass: the same lobes and bit-identical samples.
TEST(GltfBrdf, RoughDielectricAtZeroIsSmoothGlass) {
    const Material rough = Material::rough_dielectric(1.4f, 0.0f, {1.0f, 0.9f, 0.8f});
    const Material smooth = Material::dielectric(1.4f, true, {1.0f, 0.9f, 0.8f});
    EXPECT_EQ(lobes(rough), lobes(smooth));
    EXPECT_TRUE(rough.is_specular());
    Pcg32 rng(1, 2);
    for (int i = 0; i < 1000; ++i) {
        const ShadingPoint p = flat_point(i % 2 == 0, rough.albedo);
        const glm::vec3 wo = local_dir(rng.next_float(), 6.283 * rng.next_float());
        const float uc = rng.next_float();
        const glm::vec2 u = rng.next_vec2();
        const BsdfSample a = sample(rough, p, wo, uc, u), b = sample(smooth, p, wo, uc, u);
        EXPECT_EQ(a.wi, b.wi);
        EXPECT_EQ(a.weight, b.weight);
        EXPECT_EQ(a.pdf, b.pdf);
        EXPECT_EQ(a.lobe, b.lobe);
    }
}

/// Directional albedo of the glTF BRDF at wo (reflection): the specular part over
/// microfacet normals, the diffuse part (smooth) on a regular grid over wi.
double gltf_albedo(const glm::dvec3& wo, const glm::dvec3& c, double metallic, double roughness) {
    const double a = roughness * roughness;
    double e = testing::integrate_over_normals(a, [&](const glm::dvec3& h) {
        const double oh = glm::dot(wo, h);
        const glm::dvec3 wi = 2.0 * oh * h - wo;
        if (oh <= 0.0 || wi.z <= 0.0) return 0.0;
        return gltf_brdf(wo, wi, c, metallic, roughness, 2).x * wi.z * 4.0 * oh;
    });
    constexpr int nc = 400, np = 400;
    for (int i = 0; i < nc; ++i)
        for (int j = 0; j < np; ++j) {
            const glm::dvec3 wi(local_dir((i + 0.5) / nc, (j + 0.5) * 2.0 * kPi / np));
            e += gltf_brdf(wo, wi, c, metallic, roughness, 1).x * wi.z * (1.0 / nc) *
                 (2.0 * kPi / np);
        }
    return e;
}

// At grazing incidence the spec's formula reflects more than it receives (its
// fresnel_mix gives the diffuse base 1 - F(V.H) of each direction, not 1 - the specular
// albedo): the library's sampled albedo follows the spec's formula there, excess included.
TEST(GltfBrdf, GrazingAlbedoIsTheSpecs) {
    const int n = librt::testing::scaled_samples(400'000);  // 4 cases: 1.6e6 in all
    const glm::dvec3 c(0.8);
    for (const float r : {0.05f, 0.3f})
        for (const double co : {0.05, 0.2}) {
            const Material m = Material::metallic_roughness(glm::vec3(c), 0.0f, r);
            const glm::dvec3 wo(local_dir(co, 0.0));
            const double expected = gltf_albedo(wo, c, 0.0, r);
            Pcg32 rng(21, 4);
            double sum = 0.0, sum2 = 0.0;
            for (int i = 0; i < n; ++i) {
                const BsdfSample s =
                    sample(m, flat_point(), glm::vec3(wo), rng.next_float(), rng.next_vec2());
                const double w = s.valid() ? s.weight.x : 0.0;
                sum += w;
                sum2 += w * w;
            }
            const double mean = sum / n, se = std::sqrt((sum2 / n - mean * mean) / n);
            EXPECT_NEAR(mean, expected, 5.0 * se + 2e-3) << "r " << r << " cos " << co;
            if (r == 0.05f && co == 0.05) {
                EXPECT_GT(expected, 1.2) << "the spec excess";
            }
        }
}

// Furnace: a unit sphere of the BSDF inside a sphere emitting Le = 1 (which reflects
// nothing). The sphere is convex, so each reflected ray meets the emitter: a pixel sees
// Le E(mu_o), E the directional albedo at the cosine between the camera ray and the normal.
// White conductor (F = 1: GGX's single-scattering energy) and glTF materials.
TEST(GltfBrdf, FurnaceSphereRendersLeTimesAlbedo) {
    struct FurnaceCase {
        const char* name;
        Material m;
        glm::dvec3 c;
        double metallic;
    };
    const float r = 0.5f;
    const FurnaceCase cases[] = {
        {"white conductor", Material::conductor(glm::vec3(1.0f), glm::vec3(1000.0f), r),
         glm::dvec3(1.0), 1.0},
        {"gltf white metal", Material::metallic_roughness(glm::vec3(1.0f), 1.0f, r),
         glm::dvec3(1.0), 1.0},
        {"gltf white plastic", Material::metallic_roughness(glm::vec3(1.0f), 0.0f, r),
         glm::dvec3(1.0), 0.0},
        {"gltf grey half metal", Material::metallic_roughness(glm::vec3(0.6f), 0.5f, r),
         glm::dvec3(0.6), 0.5}};
    for (const FurnaceCase& fc : cases) {
        Scene scene;
        scene.add_sphere({{0, 0, 0}, 1.0f}, scene.add_material(fc.m));
        scene.add_sphere({{0, 0, 0}, 50.0f},
                         scene.add_material(Material::emissive(glm::vec3(1.0f))));
        scene.commit();
        testing::Pinhole cam;
        cam.eye = {0.0f, 0.0f, 4.0f};
        cam.fov_degrees = 20.0f;
        cam.width = cam.height = 3;
        PathTracer path({8});
        BruteForcePathTracer brute({8});
        for (Integrator* integrator :
             {static_cast<Integrator*>(&path), static_cast<Integrator*>(&brute)}) {
            const testing::StatImage img = testing::render_stats(scene, *integrator, cam, 4000, 3);
            for (int y = 0; y < cam.height; ++y)
                for (int x = 0; x < cam.width; ++x) {
                    // mu_o: where the pixel's ray meets the unit sphere.
                    const Ray ray = cam.ray(x, y);
                    const glm::dvec3 o(ray.origin), d(ray.direction);
                    const double b = glm::dot(o, d), disc = b * b - (glm::dot(o, o) - 1.0);
                    ASSERT_GT(disc, 0.0) << "every pixel sees the sphere";
                    const glm::dvec3 hit = o + (-b - std::sqrt(disc)) * d;
                    const double mu = -glm::dot(d, glm::normalize(hit));
                    const double expected =
                        fc.metallic == 1.0 && fc.c.x == 1.0
                            ? testing::ref_ggx_albedo(glm::dvec3(std::sqrt(1 - mu * mu), 0, mu),
                                                      r * r)
                            : gltf_albedo(glm::dvec3(std::sqrt(1 - mu * mu), 0, mu), fc.c,
                                          fc.metallic, r);
                    const testing::PixelStats& s = img.at(x, y);
                    const double se = std::sqrt(s.variance().x / s.n);
                    EXPECT_LT(se, 0.01) << "the test has power";
                    EXPECT_NEAR(s.mean().x, expected, 5.0 * se + 2e-4)
                        << fc.name << " pixel " << x << "," << y;
                }
        }
    }
}

}  // namespace
}  // namespace librt
