// Issue 42 item 5, emitters as lights: an emissive triangle is light-sampled only when it
// may emit something worth a light sample (TriangleLightSettings); the others stay
// visible and are found by BSDF sampling with MIS weight 1. Tested: the power a textured
// triangle light is chosen by is its texture's mean over it (a brute-force mean); on a
// ToyCar-like body (thousands of emissive triangles, an emission map black but for a few
// lamps) only the lamps' triangles become lights, and a dim glow beside them is left out;
// and with triangles left out the MIS path tracer still equals the brute-force one (which
// never samples a light), with the light tree and with the power table.

#include "light_scene_test_util.h"

#include <librt/core/constants.h>
#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/light/triangle_light.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace librt {
namespace {

using testing::add_floor_and_ball;
using testing::expect_images_agree;

// The texture's mean over the triangle of light `l`, brute force: lookups at the centres
// of a 1000 x 1000 stratification (area-preserving, as sample_uniform_triangle maps it),
// in double.
glm::dvec3 brute_mean(const TriangleLight& l) {
    constexpr int n = 1000;
    glm::dvec3 sum(0.0);
    for (int i = 0; i < n; ++i)
        for (int j = 0; j < n; ++j) {
            // Uniform on the triangle from the unit square (Shirley's square-root map).
            const double su = std::sqrt((i + 0.5) / n), v = (j + 0.5) / n;
            const double b1 = su * (1.0 - v), b2 = su * v;
            const glm::vec2 uv =
                float(1.0 - b1 - b2) * l.uv0 + float(b1) * l.uv1 + float(b2) * l.uv2;
            sum += glm::dvec3(l.texture->lookup(uv));
        }
    return sum / double(n) / double(n);
}

TriangleLight textured_triangle(std::shared_ptr<const ImageTexture> texture) {
    TriangleLight l;
    l.p0 = {0.0f, 0.0f, 0.0f};
    l.p1 = {2.0f, 0.0f, 0.0f};
    l.p2 = {0.5f, 1.5f, 0.0f};
    l.radiance = glm::vec3(3.0f, 2.0f, 1.0f);
    l.two_sided = false;
    l.texture = std::move(texture);
    l.uv0 = {0.08f, 0.11f};
    l.uv1 = {0.93f, 0.21f};
    l.uv2 = {0.32f, 0.96f};
    l.mean_texture = mean_texture_estimate(l);
    return l;
}

TEST(NegligibleEmitters, PowerOfATexturedTriangleIsItsTexturesMeanOverIt) {
    // (1) Texels uniform in [0, 1) per channel, 64 x 32: the triangle covers ~680 texels,
    // the estimate averages those whose centres it covers; the texels along its edges
    // (~100, each in or out) leave it within 1 % of the mean.
    Pcg32 rng(42, 3);
    std::vector<glm::vec3> noise(64 * 32);
    for (glm::vec3& t : noise) t = {rng.next_float(), rng.next_float(), rng.next_float()};
    // (2) Black but for one 3 x 2 block of bright texels inside the triangle (a lamp), 128 x
    // 128: ~5,400 texels covered, the lamp ~0.1 % of them. The lamp's texels are all
    // counted; the count of texels covered differs from the area by the edges' (~1 %):
    // within 2 % (the 4 x 4 lookups of the first estimate most often read 0 here, and
    // 32 x 32 strata were 20 % off).
    std::vector<glm::vec3> lamp(128 * 128, glm::vec3(0.0f));
    for (int y = 60; y < 62; ++y)
        for (int x = 50; x < 53; ++x) lamp[std::size_t(y * 128 + x)] = glm::vec3(1.0f, 0.8f, 0.5f);
    struct Case {
        ImageTexture texture;
        double tolerance;
        const char* what;
    };
    const Case cases[] = {{ImageTexture(64, 32, noise), 0.01, "uniform noise"},
                          {ImageTexture(128, 128, lamp), 0.02, "one lamp"}};
    for (const Case& c : cases) {
        const TriangleLight l = textured_triangle(std::make_shared<const ImageTexture>(c.texture));
        const glm::dvec3 mean = brute_mean(l);
        ASSERT_GT(mean.x, 0.0) << c.what;
        const double area = 0.5 * glm::length(glm::cross(l.p1 - l.p0, l.p2 - l.p0));
        const glm::vec3 p = power(l);
        for (int ch = 0; ch < 3; ++ch) {
            // power = L pi A (one side) times the mean.
            const double from_power = double(p[ch]) / (double(l.radiance[ch]) * kPi * area);
            EXPECT_NEAR(from_power / mean[ch], 1.0, c.tolerance)
                << c.what << " channel " << ch << ": " << from_power << " vs " << mean[ch];
        }
    }
}

TEST(NegligibleEmitters, MaxOverABoxBoundsEveryLookupInIt) {
    // Random boxes and lookups in them, every wrap mode and filter: never above the bound,
    // and a box over black texels only is black.
    Pcg32 rng(7, 5);
    std::vector<glm::vec3> texels(16 * 8);
    for (glm::vec3& t : texels)
        t = rng.next_float() < 0.9f ? glm::vec3(0.0f) : glm::vec3(rng.next_float());
    for (const TextureWrap wrap :
         {TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat})
        for (const TextureFilter filter : {TextureFilter::Linear, TextureFilter::Nearest}) {
            ImageTexture t(16, 8, texels);
            t.set_sampling({wrap, wrap, filter});
            int black_boxes = 0;
            for (int i = 0; i < 2000; ++i) {
                const glm::vec2 a{-2.0f + 5.0f * rng.next_float(), -2.0f + 5.0f * rng.next_float()};
                const glm::vec2 size{0.3f * rng.next_float(), 0.3f * rng.next_float()};
                const std::optional<glm::vec3> m = t.max_over(a, a + size, 1u << 20);
                ASSERT_TRUE(m.has_value());
                if (!(m->x > 0.0f)) ++black_boxes;
                for (int k = 0; k < 20; ++k) {
                    const glm::vec2 uv = a + size * glm::vec2(rng.next_float(), rng.next_float());
                    const glm::vec3 v = t.lookup(uv);
                    for (int ch = 0; ch < 3; ++ch)
                        ASSERT_LE(v[ch], (*m)[ch]) << "uv " << uv.x << ", " << uv.y;
                }
            }
            EXPECT_GT(black_boxes, 0);  // the test met black boxes too
            // A budget below the box's texels: no answer.
            EXPECT_FALSE(t.max_over({0.0f, 0.0f}, {0.9f, 0.9f}, 4).has_value());
        }
}

// ---- A ToyCar-like body: a tessellated rounded box whose whole material emits through an
// emission map that is black but for four lamps. ----

constexpr int kTexWidth = 256, kTexHeight = 128;

// The lamps' texel blocks (x0, y0, x1, y1; exclusive ends): two headlights at the front,
// two tail lights at the back (u ~ 0 and ~ 0.5), each 6 x 4 texels.
struct Block {
    int x0, y0, x1, y1;
};
const Block kLamps[] = {
    {6, 56, 12, 60}, {244, 56, 250, 60}, {116, 56, 122, 60}, {134, 56, 140, 60}};

// The emission map as 8-bit sRGB RGBA: lamps at 255, the rest black, or with `floor` > 0
// a dither of values 0..floor (a compressed map's near-black noise).
ImageTexture emission_map(int floor) {
    std::vector<std::uint8_t> rgba(std::size_t(4 * kTexWidth * kTexHeight), 0);
    Pcg32 rng(99, 1);
    for (std::size_t i = 0; i < rgba.size(); i += 4) {
        const auto v = std::uint8_t(floor > 0 ? rng.next_u32() % std::uint32_t(floor + 1) : 0);
        rgba[i] = rgba[i + 1] = rgba[i + 2] = v;
        rgba[i + 3] = 255;
    }
    for (const Block& b : kLamps)
        for (int y = b.y0; y < b.y1; ++y)
            for (int x = b.x0; x < b.x1; ++x)
                for (int c = 0; c < 3; ++c) rgba[std::size_t(4 * (y * kTexWidth + x) + c)] = 255;
    return ImageTexture::from_rgba8(kTexWidth, kTexHeight, rgba, ColorSpace::Srgb);
}

float spow(float x, float e) { return std::copysign(std::pow(std::fabs(x), e), x); }

// A rounded box (a superellipsoid, 2 x 0.6 x 0.9 m) of 2 nu nv triangles with uvs
// (longitude, latitude), wound outward.
TriangleMesh car_body(int nu, int nv) {
    TriangleMesh m;
    for (int j = 0; j <= nv; ++j) {
        const float phi = -kPi / 2 + kPi * float(j) / float(nv);
        for (int i = 0; i <= nu; ++i) {
            const float theta = 2.0f * kPi * float(i) / float(nu);
            const float c = spow(std::cos(phi), 0.35f);
            m.positions.push_back({c * spow(std::cos(theta), 0.35f),
                                   0.35f + 0.3f * spow(std::sin(phi), 0.35f),
                                   0.45f * c * spow(std::sin(theta), 0.35f)});
            m.uvs.push_back({float(i) / float(nu), float(j) / float(nv)});
        }
    }
    for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
            const auto p = std::uint32_t(j * (nu + 1) + i), q = p + std::uint32_t(nu + 1);
            m.triangles.push_back({p, q, p + 1});
            m.triangles.push_back({p + 1, q, q + 1});
        }
    return m;
}

constexpr int kNu = 120, kNv = 60;  // 14,400 triangles

Scene toycar_like(int floor, const TriangleLightSettings& settings) {
    Scene scene;
    Material body = Material::metallic_roughness(glm::vec3(0.6f, 0.05f, 0.04f), 0.0f, 0.45f);
    body.emission = glm::vec3(50.0f);
    body.emission_texture.texture = scene.add_texture(emission_map(floor));
    body.double_sided = false;
    scene.add_mesh(car_body(kNu, kNv), scene.add_material(body));
    scene.set_triangle_light_settings(settings);
    scene.commit();
    return scene;
}

// The body's triangles whose uv box, widened by a texel and a half (a bilinear lookup's
// reach plus rounding), meets a lamp block: the only ones that can emit with a black floor.
// Texture rows run down: v = 1 - (row + 0.5) / height at texel centres.
int triangles_near_lamps() {
    const TriangleMesh m = car_body(kNu, kNv);
    int count = 0;
    for (const glm::uvec3& t : m.triangles) {
        glm::vec2 lo = glm::min(glm::min(m.uvs[t.x], m.uvs[t.y]), m.uvs[t.z]);
        glm::vec2 hi = glm::max(glm::max(m.uvs[t.x], m.uvs[t.y]), m.uvs[t.z]);
        // In texel units, x right and y down.
        const float x0 = lo.x * kTexWidth - 1.5f, x1 = hi.x * kTexWidth + 1.5f;
        const float y0 = (1.0f - hi.y) * kTexHeight - 1.5f, y1 = (1.0f - lo.y) * kTexHeight + 1.5f;
        bool near = false;
        for (const Block& b : kLamps)
            for (const float shift : {-float(kTexWidth), 0.0f, float(kTexWidth)})  // u repeats
                near = near || (x1 > float(b.x0) + shift && x0 < float(b.x1) + shift &&
                                y1 > float(b.y0) && y0 < float(b.y1));
        count += near ? 1 : 0;
    }
    return count;
}

TEST(NegligibleEmitters, ToyCarLikeBodyLightSamplesOnlyItsLamps) {
    const int triangles = 2 * kNu * kNv;
    const int near = triangles_near_lamps();
    // The lamps' 4 x 24 texels cover ~ 4 x 24 / (256 x 128 / 14,400) ~ 42 triangles; with
    // their fringes, a couple of hundred at most.
    ASSERT_GT(near, 40);
    ASSERT_LT(near, 400);

    // A black floor: the triangles that cannot emit (all but those near a lamp) are no
    // lights, by default and with every rule off.
    const Scene every = toycar_like(0, {0.0f, 0.0f});
    const Scene kept = toycar_like(0, TriangleLightSettings{});
    EXPECT_LE(int(every.lights().size()), near);
    EXPECT_GT(int(every.lights().size()), 40);
    EXPECT_LE(kept.lights().size(), every.lights().size());
    EXPECT_GT(int(kept.lights().size()), 40);
    // What the defaults leave out is the lamps' faint bilinear fringe: under negligible_power
    // at most 1 % of the power, under negligible_radiance at most 1 % of the lamps'
    // radiance over the fringe's area (under three times the lamps'): together < 5 %.
    double all = 0.0, left = 0.0;
    for (const Light& l : every.lights()) all += double(power(l).x);
    for (const Light& l : kept.lights()) left += double(power(l).x);
    EXPECT_GE(left, 0.95 * all);

    // A dither floor of values 0..3 of 255 (linear <= 1e-3 against the lamps' 1): with every
    // rule off each triangle is a light; by default (negligible_radiance) the lamps' alone.
    const Scene noisy_every = toycar_like(3, {0.0f, 0.0f});
    const Scene noisy = toycar_like(3, TriangleLightSettings{});
    // The strip at each pole is degenerate (zero area, zero power): 2 nu triangles.
    EXPECT_GE(int(noisy_every.lights().size()), triangles - 2 * kNu);
    EXPECT_LE(int(noisy.lights().size()), near);
    EXPECT_GT(int(noisy.lights().size()), 40);
    EXPECT_TRUE(noisy.has_unsampled_emitters());
    // Every triangle left out still emits where hit: it has no light, and the light of
    // every kept one is a triangle near a lamp.
    std::size_t with_light = 0;
    for (std::uint32_t t = 0; t < std::uint32_t(triangles); ++t) {
        Hit hit;
        hit.object_id = 0;
        hit.primitive_id = t;
        with_light += noisy.light_of_hit(hit) != kInvalidId ? 1 : 0;
    }
    EXPECT_EQ(with_light, noisy.lights().size());
}

TEST(NegligibleEmitters, SettingsOutsideTheirRangeAreRefused) {
    Scene scene;
    for (const float bad : {-0.1f, 1.5f, std::nanf("")}) {
        EXPECT_THROW(scene.set_triangle_light_settings({bad, 0.01f}), Error);
        EXPECT_THROW(scene.set_triangle_light_settings({0.01f, bad}), Error);
    }
    try {
        scene.set_triangle_light_settings({0.01f, 2.0f});
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("negligible_radiance"), std::string::npos);
    }
}

// ---- Unbiasedness: many small emitters, some dim, some black-textured over most of
// their area, lighting the floor and ball. ----

// 12 x 12 small panels (two triangles each, facing down) over the floor at 1.6-2.2 m, a
// third of each kind: bright ones, ones 300 times dimmer (below negligible_radiance), and
// panels whose emission map is black but for the texel at uv (1, 1), which only their
// first triangle reaches (the second one's estimated power is 0).
Scene many_emitters(const TriangleLightSettings& settings) {
    Scene scene;
    add_floor_and_ball(scene);
    std::vector<glm::vec3> corner(8 * 8, glm::vec3(0.0f));
    corner[7] = glm::vec3(1.0f);  // the top row's last texel: uv (1, 1)
    ImageTexture lamp(8, 8, corner);
    lamp.set_sampling({TextureWrap::ClampToEdge, TextureWrap::ClampToEdge, TextureFilter::Linear});
    const std::int32_t lamp_texture = scene.add_texture(lamp);
    Pcg32 rng(2024, 9);
    for (int i = 0; i < 12; ++i)
        for (int j = 0; j < 12; ++j) {
            const float x = -1.8f + 0.3f * float(i), z = -1.8f + 0.3f * float(j);
            const float y = 1.6f + 0.6f * rng.next_float(), e = 0.12f;
            TriangleMesh panel;
            panel.positions = {{x, y, z}, {x + e, y, z}, {x + e, y, z + e}, {x, y, z + e}};
            panel.triangles = {{0, 1, 2}, {0, 2, 3}};  // facing down
            panel.uvs = {{0, 1}, {1, 1}, {1, 0}, {0, 0}};
            const int kind = (i + 2 * j) % 3;
            Material m = Material::diffuse(glm::vec3(0.2f));
            m.double_sided = false;
            if (kind == 0) m.emission = glm::vec3(30.0f, 20.0f, 12.0f);
            if (kind == 1) m.emission = glm::vec3(0.1f, 0.07f, 0.05f);
            if (kind == 2) {
                m.emission = glm::vec3(60.0f);
                m.emission_texture.texture = lamp_texture;
            }
            scene.add_mesh(panel, scene.add_material(m));
        }
    scene.set_triangle_light_settings(settings);
    scene.commit();
    return scene;
}

TEST(NegligibleEmitters, MisWithEmittersLeftOutEqualsBruteForce) {
    const Scene every = many_emitters({0.0f, 0.0f});
    const Scene scene = many_emitters(TriangleLightSettings{});
    // The textured panels' black triangles are never lights; by default the dim panels'
    // 96 triangles are left out too (the bright 96 and the textured panels' lit 48 stay).
    EXPECT_EQ(every.lights().size(), 240u);
    EXPECT_EQ(scene.lights().size(), 144u);
    EXPECT_GT(scene.lights().size(), LightSampler::kMaxBounded);  // the light tree chooses
    EXPECT_TRUE(scene.has_unsampled_emitters());
    PathTracerSettings s;
    s.max_depth = 3;
    BruteForcePathTracer brute(s);
    for (const bool top : {true, false}) {
        const testing::Pinhole cam = top ? testing::top_camera() : testing::side_camera();
        const testing::StatImage b = testing::render_stats(scene, brute, cam, 512, 22);
        for (const LightChoice choice : {LightChoice::Bounded, LightChoice::Power}) {
            s.light_choice = choice;
            PathTracer mis(s);
            const std::string what =
                std::string(choice == LightChoice::Bounded ? "bounded" : "power") +
                (top ? ", top" : ", side");
            const testing::StatImage a = testing::render_stats(scene, mis, cam, 64, 21);
            const testing::RegionEstimate whole = testing::region(a, 0, 0, a.width, a.height);
            EXPECT_GT(whole.mean.x, 1e-3) << what << ": black image";
            expect_images_agree(a, b, what);
        }
    }
}

}  // namespace
}  // namespace librt
