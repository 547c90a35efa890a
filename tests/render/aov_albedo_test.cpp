// The albedo AOV of each material kind, untextured and textured, against its closed form
// from the material's parameters (bsdf.h, denoising_albedo) and, where a texture is bound,
// the texture's value at each pixel's hit uv. A quad fills the view of a pinhole camera
// with one ray per pixel, so every pixel's AOV is one shading point's value. Issue 38 found
// the AOV at 1 for every glTF material: Material::albedo, not what its BSDF reflects.

#include "axis_camera.h"

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrators.h>
#include <librt/material/bsdf.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>

using namespace librt;

namespace {

constexpr int kWidth = 8, kHeight = 6;

using librt::testing::axis_camera;

// An 8 x 6 quad at z = -5 facing the camera, uvs (0, 0) to (1, 1): wider than the 60 degree
// view at that distance, so every pixel hits it, at uvs spread over most of [0, 1]^2.
TriangleMesh view_quad() {
    return make_quad({-4.0f, -3.0f, -5.0f}, {8.0f, 0.0f, 0.0f}, {0.0f, 6.0f, 0.0f});
}

// A 4 x 4 texture of distinct texels in [0.1, 0.9], nearest-texel lookups.
ImageTexture checker() {
    std::vector<glm::vec3> texels;
    for (int i = 0; i < 16; ++i)
        texels.push_back(glm::vec3(0.1f + 0.05f * float(i), 0.9f - 0.05f * float(i),
                                   0.1f + 0.05f * float((i * 7) % 16)));
    ImageTexture t(4, 4, std::move(texels));
    t.set_sampling({TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest});
    return t;
}

ImageLayers render_layers(const Scene& scene) {
    const CameraSettings cs = axis_camera(kWidth, kHeight);
    const Camera camera(cs);
    PathTracer integrator(PathTracerSettings{1, false});
    integrator.preprocess(scene);
    Film film(cs.width, cs.height, true);
    (void)render_block(scene, camera, integrator, film, {0, 0, cs.width, cs.height, 0, 2},
                       BlockSettings{});
    return resolve_layers(film);
}

// The hit of pixel (x, y)'s camera ray, found independently of the renderer.
Hit pixel_hit(const Scene& scene, int x, int y) {
    const Camera camera(axis_camera(kWidth, kHeight));
    Sampler sampler(0, 0, 0, 0);
    Hit hit;
    EXPECT_TRUE(scene.intersect(camera.generate_ray(x, y, sampler), hit));
    return hit;
}

// The texel of `slot` at the hit's uv.
glm::vec3 texel_at(const Scene& scene, const TextureSlot& slot, const Hit& hit) {
    return scene.texture(slot.texture).lookup(slot.map(hit.uv));
}

// Renders the quad in `material` and checks every pixel's albedo AOV against
// expected(hit); returns how many distinct values the pixels had.
int expect_albedo(Scene& scene, const Material& material,
                  const std::function<glm::vec3(const Hit&)>& expected) {
    (void)scene.add_mesh(view_quad(), scene.add_material(material));
    scene.commit();
    const ImageLayers layers = render_layers(scene);
    std::vector<glm::vec3> seen;
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            const glm::vec3 want = expected(pixel_hit(scene, x, y));
            const glm::vec3 got = layers.albedo.at(x, y);
            for (int c = 0; c < 3; ++c)
                EXPECT_NEAR(got[c], want[c], 1e-5f)
                    << "pixel " << x << ", " << y << " channel " << c;
            if (std::find(seen.begin(), seen.end(), got) == seen.end()) seen.push_back(got);
        }
    }
    return int(seen.size());
}

float f0_of(float ior) {
    const float r = (ior - 1.0f) / (ior + 1.0f);
    return r * r;
}

// glTF metallic-roughness: diffuse c (1 - m)(1 - t)(1 - f0) + transmitted c (1 - m) t (1 - f0)
// + specular tint (1 - m) f0 + m c.
glm::vec3 metallic_roughness_albedo(const glm::vec3& c, float metallic, float transmission,
                                    float ior) {
    const float f0 = f0_of(ior);
    return c * (1.0f - metallic) * (1.0f - transmission) * (1.0f - f0) +
           c * (1.0f - metallic) * transmission * (1.0f - f0) + glm::vec3((1.0f - metallic) * f0) +
           metallic * c;
}

// Conductor Fresnel at normal incidence: ((n - 1)^2 + k^2) / ((n + 1)^2 + k^2) per channel.
glm::vec3 conductor_f0(const glm::vec3& n, const glm::vec3& k) {
    return ((n - 1.0f) * (n - 1.0f) + k * k) / ((n + 1.0f) * (n + 1.0f) + k * k);
}

}  // namespace

TEST(AovAlbedo, DiffuseIsItsReflectanceOrItsTexel) {
    Scene plain;
    const glm::vec3 a(0.25f, 0.5f, 0.75f);
    EXPECT_EQ(expect_albedo(plain, Material::diffuse(a), [&](const Hit&) { return a; }), 1);

    Scene textured;
    Material m = Material::diffuse(glm::vec3(0.8f));
    m.albedo_texture = textured.add_texture(checker());
    const TextureSlot slot{m.albedo_texture};
    // The texel replaces the albedo (the report's map_Kd).
    EXPECT_GE(expect_albedo(textured, m, [&](const Hit& h) { return texel_at(textured, slot, h); }),
              4);
}

// The glTF material: base colour, metallic and transmission all matter; the old AOV gave
// Material::albedo, 1, for every one of these.
TEST(AovAlbedo, MetallicRoughnessIsDiffusePlusTransmittedPlusSpecularTint) {
    struct Case {
        glm::vec3 c;
        float metallic, roughness, ior, transmission;
    };
    for (const Case& k : {Case{{0.8f, 0.4f, 0.2f}, 0.0f, 0.5f, 1.5f, 0.0f},
                          Case{{0.8f, 0.4f, 0.2f}, 1.0f, 0.3f, 1.5f, 0.0f},
                          Case{{0.1f, 0.6f, 0.9f}, 0.3f, 0.7f, 2.0f, 0.0f},
                          Case{{0.9f, 0.9f, 0.5f}, 0.0f, 0.0f, 1.5f, 1.0f},  // a smooth pane
                          Case{{0.3f, 0.5f, 0.7f}, 0.2f, 0.4f, 1.3f, 0.6f}}) {
        SCOPED_TRACE("metallic " + std::to_string(k.metallic) + " transmission " +
                     std::to_string(k.transmission) + " ior " + std::to_string(k.ior));
        Scene scene;
        const glm::vec3 want = metallic_roughness_albedo(k.c, k.metallic, k.transmission, k.ior);
        EXPECT_EQ(expect_albedo(scene,
                                Material::metallic_roughness(k.c, k.metallic, k.roughness, k.ior,
                                                             k.transmission),
                                [&](const Hit&) { return want; }),
                  1);
    }
    // Worked values: white dielectric 1 (nothing lost at normal incidence); black
    // dielectric 0.04 (its specular); a half-metal red 0.5 (0.96 + 0.04) + 0.5 = 1 in red,
    // 0.02 in green and blue.
    EXPECT_NEAR(metallic_roughness_albedo(glm::vec3(1.0f), 0.0f, 0.0f, 1.5f).x, 1.0f, 1e-6f);
    EXPECT_NEAR(metallic_roughness_albedo(glm::vec3(0.0f), 0.0f, 0.0f, 1.5f).x, 0.04f, 1e-6f);
    EXPECT_NEAR(metallic_roughness_albedo({1, 0, 0}, 0.5f, 0.0f, 1.5f).x, 1.0f, 1e-6f);
    EXPECT_NEAR(metallic_roughness_albedo({1, 0, 0}, 0.5f, 0.0f, 1.5f).y, 0.02f, 1e-6f);
}

// Base colour texture times the factor, metallic times the metallic-roughness texture's B.
TEST(AovAlbedo, MetallicRoughnessTakesItsBaseColourAndMetallicTextures) {
    Scene scene;
    const glm::vec3 factor(0.9f, 0.7f, 0.5f);
    Material m = Material::metallic_roughness(factor, 0.8f, 0.5f, 1.5f, 0.25f);
    m.base_color_texture.texture = scene.add_texture(checker());
    m.metallic_roughness_texture.texture = scene.add_texture(checker());
    const Material stored = m;
    EXPECT_GE(expect_albedo(scene, m,
                            [&](const Hit& h) {
                                const glm::vec3 c =
                                    factor * texel_at(scene, stored.base_color_texture, h);
                                const float metallic =
                                    0.8f * texel_at(scene, stored.metallic_roughness_texture, h).z;
                                return metallic_roughness_albedo(c, metallic, 0.25f, 1.5f);
                            }),
              4);
}

TEST(AovAlbedo, ConductorIsItsNormalIncidenceFresnelTimesItsTint) {
    const glm::vec3 eta(0.2f, 0.9f, 1.1f), k(3.5f, 2.5f, 1.8f);
    Scene plain;
    EXPECT_EQ(expect_albedo(plain, Material::conductor(eta, k, 0.4f),
                            [&](const Hit&) { return conductor_f0(eta, k); }),
              1);
    // A tint texture (albedo_texture scales every lobe, as the path tracer applies it).
    Scene textured;
    Material m = Material::conductor(eta, k, 0.4f);
    m.albedo_texture = textured.add_texture(checker());
    const TextureSlot slot{m.albedo_texture};
    EXPECT_GE(expect_albedo(
                  textured, m,
                  [&](const Hit& h) { return texel_at(textured, slot, h) * conductor_f0(eta, k); }),
              4);
}

TEST(AovAlbedo, RoughGlassIsItsTint) {
    const glm::vec3 tint(0.9f, 0.8f, 0.6f);
    Scene plain;
    EXPECT_EQ(expect_albedo(plain, Material::rough_dielectric(1.5f, 0.4f, tint),
                            [&](const Hit&) { return tint; }),
              1);
    Scene textured;
    Material m = Material::rough_dielectric(1.5f, 0.4f);
    m.albedo_texture = textured.add_texture(checker());
    const TextureSlot slot{m.albedo_texture};
    EXPECT_GE(expect_albedo(textured, m, [&](const Hit& h) { return texel_at(textured, slot, h); }),
              4);
}

// Delta surfaces pass the AOV on: a textured mirror shows the wall behind the camera, its
// albedo tinted by the mirror's texel where the ray met the mirror; smooth glass (no
// Fresnel: always refracts) its tint times the wall behind it.
TEST(AovAlbedo, MirrorAndGlassTintTheSurfaceTheyShow) {
    const glm::vec3 wall(0.5f, 0.6f, 0.7f);
    Scene mirror;
    Material m = Material::mirror();
    m.albedo_texture = mirror.add_texture(checker());
    const TextureSlot slot{m.albedo_texture};
    (void)mirror.add_mesh(make_box({-50.0f, -50.0f, 5.0f}, {50.0f, 50.0f, 6.0f}),
                          mirror.add_material(Material::diffuse(wall)));
    EXPECT_GE(
        expect_albedo(mirror, m, [&](const Hit& h) { return texel_at(mirror, slot, h) * wall; }),
        4);

    Scene glass;
    const glm::vec3 tint(0.9f, 0.7f, 0.8f);
    (void)glass.add_mesh(make_box({-50.0f, -50.0f, -9.0f}, {50.0f, 50.0f, -8.0f}),
                         glass.add_material(Material::diffuse(wall)));
    // One face of glass (a quad): refracted in, the ray meets the wall inside the "glass".
    EXPECT_EQ(expect_albedo(glass, Material::dielectric(1.5f, false, tint),
                            [&](const Hit&) { return tint * wall; }),
              1);
}

// An emitter reflects nothing, whatever its emission texture.
TEST(AovAlbedo, EmitterIsBlackTexturedOrNot) {
    Scene plain;
    EXPECT_EQ(expect_albedo(plain, Material::emissive(glm::vec3(2.0f)),
                            [](const Hit&) { return glm::vec3(0.0f); }),
              1);
    Scene textured;
    Material m = Material::emissive(glm::vec3(2.0f));
    m.emission_texture.texture = textured.add_texture(checker());
    EXPECT_EQ(expect_albedo(textured, m, [](const Hit&) { return glm::vec3(0.0f); }), 1);
}

// The debug view shows the same value as the AOV (it showed Material::albedo, 1, too).
TEST(AovAlbedo, AlbedoDebugViewMatchesTheAov) {
    Scene scene;
    Material m = Material::metallic_roughness({0.9f, 0.7f, 0.5f}, 0.4f, 0.5f);
    m.base_color_texture.texture = scene.add_texture(checker());
    (void)scene.add_mesh(view_quad(), scene.add_material(m));
    scene.commit();
    const ImageLayers layers = render_layers(scene);
    const Camera camera(axis_camera(kWidth, kHeight));
    const AlbedoNormalIntegrator view(DebugView::Albedo);
    for (int y = 0; y < kHeight; ++y) {
        for (int x = 0; x < kWidth; ++x) {
            Sampler sampler(0, 0, 0, 0);
            const Ray ray = camera.generate_ray(x, y, sampler);
            const glm::vec3 shown = view.li(scene, ray, sampler);
            for (int c = 0; c < 3; ++c) EXPECT_NEAR(shown[c], layers.albedo.at(x, y)[c], 1e-6f);
        }
    }
}
