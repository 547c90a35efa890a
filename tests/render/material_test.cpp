// Materials, lights, textures and the specular scattering of the dielectric BSDF (incl. a
// glass slab).

#include "material/specular.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/io/texture_io.h>
#include <librt/light/light.h>
#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/material/texture.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

namespace librt {
using librt::testing::error_of;

namespace {

/// What the dielectric BSDF does to a world direction d (toward the surface) at a surface
/// of unit outward normal n: the BSDF seam's sample() in the frame ShadingFrame::at builds.
struct WorldScatter {
    glm::vec3 direction{0.0f};  ///< unit outgoing direction, world
    bool transmitted = false;   ///< crossed the surface
    float pdf = 0.0f;           ///< probability of the lobe chosen
};

WorldScatter scatter(const Material& m, const glm::vec3& d, const glm::vec3& n, float u) {
    const ShadingPoint sp{ShadingFrame::at(n, n, d), m.albedo};
    const BsdfSample s = sample(m, sp, sp.frame.to_local(-d), u, glm::vec2(0.5f));
    EXPECT_TRUE(s.valid());
    EXPECT_TRUE(has(s.lobe, BsdfLobe::Specular));
    return {sp.frame.to_world(s.wi), has(s.lobe, BsdfLobe::Transmission), s.pdf};
}

TEST(Material, FactoriesSetKindAndDefaults) {
    const Material d = Material::diffuse({0.2f, 0.4f, 0.6f});
    EXPECT_EQ(d.kind, MaterialKind::Diffuse);
    EXPECT_EQ(d.albedo, glm::vec3(0.2f, 0.4f, 0.6f));
    EXPECT_FALSE(d.emits());
    EXPECT_FALSE(d.is_specular());
    const Material m = Material::mirror();
    EXPECT_EQ(m.kind, MaterialKind::Mirror);
    EXPECT_EQ(m.albedo, glm::vec3(1.0f));
    EXPECT_TRUE(m.is_specular());
    const Material g = Material::dielectric(1.4f, false);
    EXPECT_EQ(g.kind, MaterialKind::Dielectric);
    EXPECT_FLOAT_EQ(g.ior, 1.4f);
    EXPECT_FALSE(g.fresnel);
    EXPECT_EQ(g.albedo, glm::vec3(1.0f));
    const Material e = Material::emissive({1, 2, 3});
    EXPECT_EQ(e.kind, MaterialKind::Emissive);
    EXPECT_TRUE(e.emits());
}

TEST(Material, ValidationNamesParameterAndValue) {
    EXPECT_NE(error_of([] {
                  (void)Material::diffuse({0.5f, -0.1f, 0.5f});
              }).find("albedo = (0.5, -0.1, 0.5)"),
              std::string::npos);
    EXPECT_NE(error_of([] { (void)Material::dielectric(-1.0f); }).find("ior = -1"),
              std::string::npos);
    EXPECT_NE(error_of([] { (void)Material::dielectric(NAN); }).find("ior = nan"),
              std::string::npos);
    EXPECT_NE(error_of([] {
                  (void)Material::emissive({INFINITY, 0, 0});
              }).find("emission = (inf"),
              std::string::npos);
    Material glowing = Material::diffuse(glm::vec3(0.5f));
    glowing.emission = glm::vec3(2.0f);  // emission on any kind is allowed
    EXPECT_NO_THROW(validate(glowing));
}

TEST(Light, PointLightFromPowerAndSphereLightOfTheSamePowerAgreeFarAway) {
    const float power = 2.14e8f;  // the report's I
    const PointLight p = PointLight::from_power({0, 0, 0}, power);
    EXPECT_FLOAT_EQ(p.intensity.x, power / (4.0f * 3.14159265f));
    const float r = 0.5f;
    const glm::vec3 radiance = SphereLight::radiance_for_power(power, r);
    // Emitted power of a uniform sphere emitter: L * pi * 4 pi r^2.
    EXPECT_NEAR(radiance.x * kPi * 4.0f * kPi * r * r / power, 1.0f, 1e-6f);
    // Irradiance at distance d facing the centre: point I / d^2; sphere L pi sin^2(theta_max).
    const float d = 1000.0f;
    const float e_point = p.intensity.x / (d * d);
    const float e_sphere = radiance.x * kPi * (r * r) / (d * d);
    EXPECT_NEAR(e_sphere / e_point, 1.0f, 1e-5f);
}

TEST(Light, ValidationNamesParameter) {
    EXPECT_NE(error_of([] {
                  validate(PointLight{{0, NAN, 0}, {1, 1, 1}});
              }).find("position"),
              std::string::npos);
    EXPECT_NE(error_of([] {
                  validate(SphereLight{{{0, 0, 0}, -1.0f}, {1, 1, 1}});
              }).find("radius = -1"),
              std::string::npos);
    EXPECT_NE(error_of([] {
                  validate(SphereLight{{{0, 0, 0}, 1.0f}, {-1, 1, 1}});
              }).find("radiance"),
              std::string::npos);
}

TEST(Texture, SrgbDecoding) {
    EXPECT_FLOAT_EQ(srgb_to_linear(0.0f), 0.0f);
    EXPECT_NEAR(srgb_to_linear(1.0f), 1.0f, 1e-6f);
    EXPECT_NEAR(srgb_to_linear(0.5f), 0.21404f, 1e-4f);
    EXPECT_NEAR(srgb_to_linear(0.04f), 0.04f / 12.92f, 1e-7f);
}

TEST(Texture, BilinearRepeatAndVFlip) {
    // 2 x 2, row 0 on top: top-left red, top-right green, bottom-left blue, bottom-right white.
    const ImageTexture tex(2, 2, {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 1}});
    // Texel centres: u = 0.25 / 0.75; v = 0.75 is the top row (v flipped).
    EXPECT_EQ(tex.lookup({0.25f, 0.75f}), glm::vec3(1, 0, 0));
    EXPECT_EQ(tex.lookup({0.75f, 0.75f}), glm::vec3(0, 1, 0));
    EXPECT_EQ(tex.lookup({0.25f, 0.25f}), glm::vec3(0, 0, 1));
    // Half way between top-left and top-right.
    const glm::vec3 mid = tex.lookup({0.5f, 0.75f});
    EXPECT_NEAR(mid.x, 0.5f, 1e-6f);
    EXPECT_NEAR(mid.y, 0.5f, 1e-6f);
    // Repeat: integer shifts change nothing, and u = 0 blends the left and right columns.
    for (const glm::vec2 uv : {glm::vec2(0.3f, 0.6f), glm::vec2(0.9f, 0.1f)}) {
        const glm::vec3 a = tex.lookup(uv), b = tex.lookup(uv + glm::vec2(3.0f, -2.0f));
        EXPECT_NEAR(glm::length(a - b), 0.0f, 1e-5f);
    }
    const glm::vec3 edge = tex.lookup({0.0f, 0.75f});
    EXPECT_NEAR(edge.x, 0.5f, 1e-6f);
    // Non-finite coordinates give a texel, not NaN.
    const glm::vec3 nan = tex.lookup({NAN, 0.5f});
    EXPECT_TRUE(std::isfinite(nan.x + nan.y + nan.z));
}

TEST(Texture, RejectsBadSizes) {
    EXPECT_THROW(ImageTexture(0, 1, {}), Error);
    EXPECT_THROW(ImageTexture(2, 2, {{1, 1, 1}}), Error);
}

TEST(Texture, LoadsAnImageAndNamesTheMissingPath) {
    // A 2 x 1 binary PPM, which stb_image reads: sRGB 255 red, 128 green.
    const auto path = std::filesystem::temp_directory_path() / "librt_texture_test.ppm";
    {
        std::ofstream out(path, std::ios::binary);
        out << "P6\n2 1\n255\n";
        const unsigned char px[6] = {255, 0, 0, 0, 128, 0};
        out.write(reinterpret_cast<const char*>(px), 6);
    }
    const ImageTexture tex = load_texture(path);
    std::filesystem::remove(path);
    ASSERT_EQ(tex.width(), 2);
    ASSERT_EQ(tex.height(), 1);
    EXPECT_NEAR(tex.texel(0, 0).x, 1.0f, 1e-6f);
    EXPECT_NEAR(tex.texel(1, 0).y, srgb_to_linear(128.0f / 255.0f), 1e-6f);
    const std::string missing = "/nonexistent/librt/albedo.png";
    EXPECT_NE(error_of([&] { (void)load_texture(missing); }).find(missing), std::string::npos);
}

TEST(Scatter, ReflectAndSchlick) {
    const glm::vec3 n(0, 1, 0);
    const glm::vec3 d = glm::normalize(glm::vec3(1, -1, 0));
    EXPECT_NEAR(glm::length(reflect(d, n) - glm::normalize(glm::vec3(1, 1, 0))), 0.0f, 1e-6f);
    EXPECT_NEAR(schlick_fresnel(1.0f, 1.0f, 1.5f), 0.04f, 1e-6f);  // R0 at normal incidence
    EXPECT_NEAR(schlick_fresnel(0.0f, 1.0f, 1.5f), 1.0f, 1e-6f);   // grazing
}

TEST(Scatter, SnellRefractionAndTotalInternalReflection) {
    const glm::vec3 n(0, 1, 0);  // outward
    const float ior = 1.5f;
    const Material glass = Material::dielectric(ior, false);
    const float theta_i = 0.7f;
    const glm::vec3 d(std::sin(theta_i), -std::cos(theta_i), 0.0f);
    const WorldScatter in = scatter(glass, d, n, 0.0f);
    ASSERT_TRUE(in.transmitted);
    // Snell: sin(theta_t) = sin(theta_i) / ior, and the ray keeps going down.
    EXPECT_NEAR(in.direction.x, std::sin(theta_i) / ior, 1e-6f);
    EXPECT_LT(in.direction.y, 0.0f);
    EXPECT_NEAR(glm::length(in.direction), 1.0f, 1e-6f);
    // Inside beyond the critical angle asin(1/1.5) = 0.7297: total internal reflection,
    // even without Fresnel.
    const float steep = 0.9f;
    const glm::vec3 up(std::sin(steep), std::cos(steep), 0.0f);
    const WorldScatter tir = scatter(glass, up, n, 0.0f);
    EXPECT_FALSE(tir.transmitted);
    EXPECT_EQ(tir.pdf, 1.0f);  // without Fresnel, reflecting at all means total reflection
    EXPECT_NEAR(tir.direction.y, -std::cos(steep), 1e-6f);
    // Just below the critical angle from inside: refracts out, grazing.
    const float below = std::asin(1.0f / ior) - 1e-3f;
    const WorldScatter out = scatter(glass, {std::sin(below), std::cos(below), 0.0f}, n, 0.0f);
    EXPECT_TRUE(out.transmitted);
    EXPECT_GT(out.direction.y, 0.0f);
}

TEST(Scatter, FresnelReflectsWithProbabilitySchlick) {
    const glm::vec3 n(0, 0, 1);
    const glm::vec3 d = glm::normalize(glm::vec3(0.8f, 0.0f, -0.6f));
    const float f = schlick_fresnel(0.6f, 1.0f, 1.5f);
    const Material glass = Material::dielectric(1.5f, true);
    // u on a regular grid: the reflected fraction is F up to the grid step.
    const int count = 100000;
    int reflected = 0;
    for (int i = 0; i < count; ++i) {
        const WorldScatter s = scatter(glass, d, n, (float(i) + 0.5f) / float(count));
        reflected += !s.transmitted;
        // The probability of the lobe chosen, as sample() reports it.
        ASSERT_NEAR(s.pdf, s.transmitted ? 1.0f - f : f, 1e-6f);
    }
    EXPECT_NEAR(double(reflected) / count, f, 2.0 / count);
}

// A glass slab made of two parallel quads (top facing +y at y = 1, bottom facing -y at
// y = 0): a ray traced through the scene with the dielectric BSDF leaves
// with its original direction, shifted sideways by t sin(theta_i - theta_t) / cos(theta_t).
TEST(Scatter, GlassSlabLeavesDirectionUnchanged) {
    Scene scene;
    const auto glass = scene.add_material(Material::dielectric(1.5f, false));
    const float s = 100.0f;
    scene.add_triangle({{-s, 1, -s}, {-s, 1, s}, {s, 1, s}}, glass);  // (p1-p0)x(p2-p0) = +y
    scene.add_triangle({{-s, 1, -s}, {s, 1, s}, {s, 1, -s}}, glass);
    scene.add_triangle({{-s, 0, -s}, {s, 0, s}, {-s, 0, s}}, glass);  // -y
    scene.add_triangle({{-s, 0, -s}, {s, 0, -s}, {s, 0, s}}, glass);
    scene.commit();
    for (const float theta_i : {0.0f, 0.3f, 0.8f, 1.3f, 1.55f}) {
        const glm::vec3 d0(std::sin(theta_i), -std::cos(theta_i), 0.0f);
        Ray ray{{0.1f, 3.0f, 0.2f}, d0};
        int interfaces = 0;
        Hit hit;
        glm::vec3 entry(0.0f), exit(0.0f);
        float entry_offset = 0.0f;
        while (scene.intersect(ray, hit) && interfaces < 10) {
            const Material& m = scene.material(hit);
            ASSERT_EQ(m.kind, MaterialKind::Dielectric);
            const WorldScatter sc = scatter(m, ray.direction, hit.geometric_normal, 0.5f);
            ASSERT_TRUE(sc.transmitted) << "theta_i " << theta_i;
            if (interfaces == 0) {
                entry = hit.point;
                entry_offset = hit.offset;
                // Inside: Snell's angle.
                EXPECT_NEAR(sc.direction.x, std::sin(theta_i) / 1.5f, 1e-6f);
            } else {
                exit = hit.point;
            }
            ray = spawn_ray(hit, sc.direction);
            ++interfaces;
        }
        ASSERT_EQ(interfaces, 2) << "theta_i " << theta_i;
        EXPECT_NEAR(glm::length(ray.direction - d0), 0.0f, 2e-6f) << "theta_i " << theta_i;
        // Inside the slab the ray went down by 1 at the refracted angle.
        const float theta_t = std::asin(std::sin(theta_i) / 1.5f);
        // The exit ray starts the hit's offset below the top face, hence a shorter shift.
        EXPECT_NEAR(exit.x - entry.x, std::tan(theta_t),
                    1e-4f + 2.0f * entry_offset * std::tan(theta_t));
    }
}

}  // namespace
}  // namespace librt
