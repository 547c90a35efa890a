// One-sided and textured emissive triangles are light-sampled (issue 12, items 6 and 10):
// a one-sided emitter's triangle lights emit from the front only, with half the power, and
// its light samples from behind are rejected; a textured one's light samples carry the
// texture at the sampled point; the MIS path tracer equals the brute-force one for both.

#include "light/light_bounds.h"
#include "light_scene_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

namespace librt {
namespace {

using testing::add_floor_and_ball;
using testing::expect_mis_equals_brute;

/// A glTF-like emitter: a dark rough plastic that glows, single-sided unless asked.
Material glowing(const glm::vec3& emission, bool double_sided) {
    Material m = Material::metallic_roughness(glm::vec3(0.1f), 0.0f, 0.6f);
    m.emission = emission;
    m.double_sided = double_sided;
    return m;
}

/// A 1.2 x 1.2 panel at height y, its winding's normal down (-y) or up.
TriangleMesh panel(float y, bool facing_down) {
    TriangleMesh mesh;
    mesh.positions = {{-0.6f, y, -0.6f}, {0.6f, y, -0.6f}, {0.6f, y, 0.6f}, {-0.6f, y, 0.6f}};
    // (1,0,0) x (1,0,1) = (0,-1,0): these windings face down.
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    if (!facing_down)
        for (glm::uvec3& t : mesh.triangles) std::swap(t.y, t.z);
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    return mesh;
}

/// The panel's lights after commit (the scene holds nothing else that emits).
std::vector<const Light*> triangle_lights(const Scene& scene) {
    std::vector<const Light*> out;
    for (const Light& l : scene.lights())
        if (std::holds_alternative<TriangleLight>(l.source)) out.push_back(&l);
    return out;
}

TEST(EmitterLights, OneSidedEmitterIsAOneSidedLightWithHalfThePower) {
    Scene one, two;
    for (Scene* s : {&one, &two}) {
        s->add_mesh(panel(2.0f, true),
                    s->add_material(glowing(glm::vec3(3.0f, 2.0f, 1.0f), s == &two)));
        s->commit();
        EXPECT_FALSE(s->has_unsampled_emitters());
    }
    const auto a = triangle_lights(one), b = triangle_lights(two);
    ASSERT_EQ(a.size(), 2u);
    ASSERT_EQ(b.size(), 2u);
    for (int i = 0; i < 2; ++i) {
        EXPECT_TRUE(a[i]->one_sided);
        EXPECT_FALSE(b[i]->one_sided);
        const glm::vec3 pa = power(*a[i]), pb = power(*b[i]);
        for (int c = 0; c < 3; ++c) EXPECT_NEAR(pa[c] / pb[c], 0.5f, 1e-6f) << i << c;
        // One side: L pi A, A = 0.72 per triangle (pbrt 4th ed. 12.5).
        EXPECT_NEAR(pa.x, 3.0f * kPi * 0.72f, 1e-4f);
        // The bound's cone is the front hemisphere (axis down, cos 0); none when two-sided.
        const LightBounds lb = light_bounds(*a[i]);
        EXPECT_TRUE(lb.cone);
        EXPECT_NEAR(lb.axis.y, -1.0f, 1e-6f);
        EXPECT_EQ(lb.cos_cone, 0.0f);
        EXPECT_FALSE(light_bounds(*b[i]).cone);
    }
}

TEST(EmitterLights, OneSidedLightSamplesFromBehindAreRejected) {
    Scene scene;
    scene.add_mesh(panel(2.0f, true), scene.add_material(glowing(glm::vec3(2.0f), false)));
    scene.commit();
    const auto lights = triangle_lights(scene);
    ASSERT_EQ(lights.size(), 2u);
    Pcg32 rng(5, 3);
    const glm::vec3 above{0.1f, 2.7f, -0.2f}, below{0.1f, 1.3f, -0.2f};
    int valid_below = 0;
    for (const Light* l : lights)
        for (int i = 0; i < 4000; ++i) {
            const glm::vec2 u{rng.next_float(), rng.next_float()};
            const LightLiSample back = sample_li(*l, above, u);
            EXPECT_FALSE(back.valid()) << "a sample from behind the panel";
            const LightLiSample front = sample_li(*l, below, u);
            valid_below += front.valid() ? 1 : 0;
            if (!front.valid()) continue;
            // pdf_li agrees: the density of the sample in front, 0 from behind toward
            // the same point of the panel.
            EXPECT_NEAR(pdf_li(*l, below, front.wi), front.pdf, 2e-3f * front.pdf);
            const glm::vec3 p = below + front.distance * front.wi;
            EXPECT_EQ(pdf_li(*l, above, glm::normalize(p - above)), 0.0f);
        }
    EXPECT_EQ(valid_below, 8000) << "every sample from in front is valid";
    // In front, one-sidedness changes nothing: the same samples as the two-sided light's.
    Scene two;
    two.add_mesh(panel(2.0f, true), two.add_material(glowing(glm::vec3(2.0f), true)));
    two.commit();
    const auto both = triangle_lights(two);
    for (int i = 0; i < 2; ++i) {
        const auto e1 = testing::irradiance_by_sampling(*lights[i], below, {0, 1, 0}, 20000, 9);
        const auto e2 = testing::irradiance_by_sampling(*both[i], below, {0, 1, 0}, 20000, 9);
        EXPECT_EQ(e1.mean.x, e2.mean.x);
        EXPECT_GT(e1.mean.x, 0.0);
    }
}

TEST(EmitterLights, OneSidedPanelFacingTheSceneMisEqualsBruteForce) {
    Scene scene;
    add_floor_and_ball(scene);
    scene.add_mesh(panel(2.2f, true),
                   scene.add_material(glowing(glm::vec3(4.0f, 3.0f, 2.0f), false)));
    scene.commit();
    EXPECT_FALSE(scene.has_unsampled_emitters());
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 256, "one-sided panel, down");
    expect_mis_equals_brute(scene, testing::side_camera(), 32, 256, "one-sided panel, side");
}

TEST(EmitterLights, OneSidedPanelFacingAwayMisEqualsBruteForce) {
    Scene scene;
    add_floor_and_ball(scene);
    // Facing up, toward a white ceiling above it that lights the floor: all the floor gets
    // is that bounce (and none of the panel's back).
    scene.add_mesh(panel(2.2f, false), scene.add_material(glowing(glm::vec3(8.0f), false)));
    TriangleMesh ceiling = panel(2.6f, true);
    for (glm::vec3& p : ceiling.positions) p *= glm::vec3(2.0f, 1.0f, 2.0f);
    scene.add_mesh(ceiling, scene.add_material(Material::diffuse(glm::vec3(0.9f))));
    scene.commit();
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 256, "one-sided panel, up");
}

/// A 4 x 4 texture of distinct colours, so a wrong uv shows.
ImageTexture checker() {
    std::vector<glm::vec3> texels;
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            texels.push_back({0.1f + 0.3f * float(x), 0.2f + 0.25f * float(y),
                              float((x + y) % 2) * 0.9f + 0.05f});
    return ImageTexture(4, 4, std::move(texels));
}

Scene textured_panel_scene(bool double_sided) {
    Scene scene;
    add_floor_and_ball(scene);
    Material m = glowing(glm::vec3(6.0f, 5.0f, 4.0f), double_sided);
    m.emission_texture.texture = scene.add_texture(checker());
    scene.add_mesh(panel(2.2f, true), scene.add_material(m));
    scene.commit();
    return scene;
}

TEST(EmitterLights, TexturedLightSamplesCarryTheTextureOfTheSampledPoint) {
    const Scene scene = textured_panel_scene(false);
    const auto lights = triangle_lights(scene);
    ASSERT_EQ(lights.size(), 2u);
    Pcg32 rng(17, 1);
    const glm::vec3 ref{1.3f, 0.5f, -0.1f};  // on the floor, beside the ball
    int checked = 0;
    for (int i = 0; i < 2000; ++i) {
        const Light& l = *lights[std::size_t(i % 2)];
        const LightLiSample s = sample_li(l, ref, {rng.next_float(), rng.next_float()});
        ASSERT_TRUE(s.valid());
        // A camera-like ray toward the sampled point sees what shade() gives there.
        Hit hit;
        if (!scene.intersect(Ray{ref, s.wi}, hit)) continue;
        if (std::fabs(hit.t - s.distance) > 1e-3f * s.distance) continue;  // the ball
        ShadedMaterial scratch;
        const Material& m = scene.shade(hit, s.wi, scratch);
        for (int c = 0; c < 3; ++c)
            EXPECT_NEAR(s.radiance[c], m.emission[c], 1e-4f * (1.0f + m.emission[c]));
        ++checked;
    }
    EXPECT_GT(checked, 1000);
    // Power uses the mean texture estimate: between the texture's extremes times L pi A.
    for (const Light* l : lights) {
        const glm::vec3 p = power(*l) / (kPi * 0.72f * glm::vec3(6.0f, 5.0f, 4.0f));
        EXPECT_GE(p.x, 0.1f);  // the red channel's least and greatest texels
        EXPECT_LE(p.x, 1.0f);
    }
}

TEST(EmitterLights, TexturedPanelMisEqualsBruteForce) {
    for (const bool double_sided : {false, true}) {
        const Scene scene = textured_panel_scene(double_sided);
        EXPECT_FALSE(scene.has_unsampled_emitters());
        expect_mis_equals_brute(scene, testing::top_camera(), 32, 256,
                                double_sided ? "textured two-sided" : "textured one-sided");
        expect_mis_equals_brute(
            scene, testing::side_camera(), 32, 256,
            double_sided ? "textured two-sided, side" : "textured one-sided, side");
    }
}

TEST(EmitterLights, CutOutEmittersAreLeftToBsdfSampling) {
    Scene scene;
    Material m = glowing(glm::vec3(2.0f), true);
    m.alpha = 0.3f;
    m.alpha_cutoff = 0.5f;
    scene.add_mesh(panel(2.0f, true), scene.add_material(m));
    scene.commit();
    EXPECT_TRUE(triangle_lights(scene).empty());
    EXPECT_TRUE(scene.has_unsampled_emitters());
}

}  // namespace
}  // namespace librt
