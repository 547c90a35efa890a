// Every light kind answers for itself (light/light.h): what its type() says agrees with
// what its sampling does, its surface_normal with the normals of the rays it emits, its
// bounds() with the points and directions it emits from and into, and preprocess with the
// power of a light at infinity. Guards docs/architecture.md's checklist for a new light:
// a LightSource alternative without examples() here fails to compile, and one whose
// members disagree with its sampling fails below.

#include "light/light_bounds.h"
#include "light/light_kind.h"

#include <librt/light/light.h>
#include <librt/sampling/rng.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <type_traits>
#include <utility>
#include <variant>
#include <vector>

namespace librt {
namespace {

// The checklist's step 1 for a dummy kind: the members and functions LightKind asks for
// (light_kind.h, asserted of every LightSource alternative in light.cpp). Each variant
// below lacks one answer and is not a light kind, so forgetting a step fails to compile.
struct DummyLight {
    [[nodiscard]] LightType type() const { return LightType::DeltaPosition; }
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const { return {}; }
    [[nodiscard]] LightBounds bounds() const { return {}; }
    void preprocess(const SceneSummary& /*scene*/) {}
};
LightLiSample sample_li(const DummyLight& /*l*/, const glm::vec3& /*ref*/, glm::vec2 /*u*/) {
    return {};
}
float pdf_li(const DummyLight& /*l*/, const glm::vec3& /*ref*/, const glm::vec3& /*p*/) {
    return 0.0f;
}
glm::vec3 power(const DummyLight& /*l*/) { return {}; }
static_assert(LightKind<DummyLight>);

struct NoType {
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const { return {}; }
    [[nodiscard]] LightBounds bounds() const { return {}; }
    void preprocess(const SceneSummary& /*scene*/) {}
};
struct NoPreprocess {
    [[nodiscard]] LightType type() const { return LightType::Area; }
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const { return {}; }
    [[nodiscard]] LightBounds bounds() const { return {}; }
};
struct NoSampling {  // the members, but no sample_li / pdf_li / power
    [[nodiscard]] LightType type() const { return LightType::Area; }
    [[nodiscard]] glm::vec3 surface_normal(const glm::vec3& /*p*/) const { return {}; }
    [[nodiscard]] LightBounds bounds() const { return {}; }
    void preprocess(const SceneSummary& /*scene*/) {}
};
struct WrongNormal {  // surface_normal answering the wrong type
    [[nodiscard]] LightType type() const { return LightType::Area; }
    [[nodiscard]] float surface_normal(const glm::vec3& /*p*/) const { return 0.0f; }
    [[nodiscard]] LightBounds bounds() const { return {}; }
    void preprocess(const SceneSummary& /*scene*/) {}
};
LightLiSample sample_li(const WrongNormal& /*l*/, const glm::vec3& /*ref*/, glm::vec2 /*u*/) {
    return {};
}
float pdf_li(const WrongNormal& /*l*/, const glm::vec3& /*ref*/, const glm::vec3& /*p*/) {
    return 0.0f;
}
glm::vec3 power(const WrongNormal& /*l*/) { return {}; }
static_assert(!LightKind<NoType> && !LightKind<NoPreprocess> && !LightKind<NoSampling> &&
              !LightKind<WrongNormal>);

// One or more examples of each kind, as Scene adds them; no fallback, so a new
// LightSource alternative needs its own overload here before this file compiles.

std::vector<PointLight> examples(std::type_identity<PointLight> /*kind*/) {
    return {PointLight{{0.5f, 2.0f, -0.3f}, {10, 20, 30}}};
}
std::vector<SpotLight> examples(std::type_identity<SpotLight> /*kind*/) {
    return {SpotLight{{0.2f, 2.5f, 0.1f}, {0.2f, -1.0f, 0.1f}, {10, 8, 6}, 0.3f, 0.6f}};
}
std::vector<SphereLight> examples(std::type_identity<SphereLight> /*kind*/) {
    return {SphereLight{{{0.3f, 2.0f, 0.2f}, 0.4f}, {2.0f, 1.0f, 0.5f}}};
}
std::vector<QuadLight> examples(std::type_identity<QuadLight> /*kind*/) {
    const QuadLight one_sided{
        {-0.5f, 2.0f, -0.4f}, {0.9f, 0.1f, 0.0f}, {0.0f, -0.1f, 0.8f}, {3, 2, 1}, false};
    QuadLight two_sided = one_sided;
    two_sided.two_sided = true;
    return {one_sided, two_sided};
}
std::vector<DiskLight> examples(std::type_identity<DiskLight> /*kind*/) {
    const DiskLight one_sided{{0.1f, 2.2f, 0.3f}, {0.2f, -1.0f, 0.1f}, 0.6f, {1, 2, 3}, false};
    DiskLight two_sided = one_sided;
    two_sided.two_sided = true;
    return {one_sided, two_sided};
}
std::vector<TriangleLight> examples(std::type_identity<TriangleLight> /*kind*/) {
    TriangleLight t;  // Scene::commit makes it from an emissive mesh (add_to below)
    t.p0 = {-0.6f, 2.1f, -0.5f};
    t.p1 = {0.1f, 2.3f, 0.7f};
    t.p2 = {0.8f, 1.9f, -0.4f};
    t.radiance = {2, 3, 1};
    TriangleLight one_sided = t;
    one_sided.two_sided = false;
    return {t, one_sided};
}
std::vector<DirectionalLight> examples(std::type_identity<DirectionalLight> /*kind*/) {
    return {DirectionalLight{{0.3f, 1.0f, -0.2f}, {3, 2, 1}, 0.0f},
            DirectionalLight{{0.3f, 1.0f, -0.2f}, {3, 2, 1}, 0.2f}};
}
std::vector<EnvironmentLight> examples(std::type_identity<EnvironmentLight> /*kind*/) {
    EnvironmentImage image{8, 4, {}};
    for (int i = 0; i < image.width * image.height; ++i)
        image.pixels.push_back(
            glm::vec3(0.1f + 0.05f * float(i % 7), 0.3f, 0.2f + 0.1f * float(i % 3)));
    return {EnvironmentLight::constant({0.5f, 1.0f, 2.0f}), EnvironmentLight::from_image(image)};
}

/// Adds the light to the scene as an app does.
void add_to(Scene& scene, const PointLight& l) { scene.add_point_light(l); }
void add_to(Scene& scene, const SpotLight& l) { scene.add_spot_light(l); }
void add_to(Scene& scene, const SphereLight& l) { scene.add_sphere_light(l); }
void add_to(Scene& scene, const QuadLight& l) { scene.add_quad_light(l); }
void add_to(Scene& scene, const DiskLight& l) { scene.add_disk_light(l); }
void add_to(Scene& scene, const DirectionalLight& l) { scene.add_directional_light(l); }
void add_to(Scene& scene, const EnvironmentLight& l) { scene.add_environment_light(l); }
void add_to(Scene& scene, const TriangleLight& l) {
    Material m = Material::emissive(l.radiance);
    m.double_sided = l.two_sided;
    TriangleMesh mesh;
    mesh.positions = {l.p0, l.p1, l.p2};
    mesh.triangles = {{0, 1, 2}};
    scene.add_mesh(mesh, scene.add_material(m));
}

/// A committed scene holding the light (lights()[0]) and, far below, a grey ball that
/// gives it a size and lies in the way of no sample drawn from kRefs.
Scene scene_with(const auto& light) {
    Scene scene;
    add_to(scene, light);
    scene.add_sphere({{0.0f, -20.0f, 0.0f}, 1.0f},
                     scene.add_material(Material::diffuse(glm::vec3(0.5f))));
    scene.commit();
    return scene;
}

/// Shading points the lights are sampled from: above, beside and below them.
const glm::vec3 kRefs[] = {{0.1f, 0.2f, 0.05f}, {2.5f, 1.8f, -1.0f}, {-0.4f, 4.0f, 0.6f}};
constexpr int kSamples = 300;
/// The rounding of a dot product of two float unit vectors that are meant to be equal.
constexpr float kRounding = 1e-6f;

bool near(const glm::vec3& a, const glm::vec3& b, float tolerance) {
    return glm::length(a - b) <= tolerance;
}

/// Checks one light of the scene's kind against its own sampling.
void check(const Scene& scene, const std::string& what) {
    ASSERT_FALSE(scene.lights().empty()) << what;
    const Light& light = scene.lights()[0];
    const LightType type = light_type(light);
    const LightBounds b = light_bounds(light);
    const SceneSphere sphere = scene.bounding_sphere();
    EXPECT_EQ(b.infinite, is_at_infinity(type)) << what;
    EXPECT_EQ(is_infinite(light), is_at_infinity(type)) << what;
    EXPECT_GT(b.phi, 0.0f) << what;
    Pcg32 rng(3, 11);
    int li_valid = 0, le_valid = 0, area_hits = 0, area_pdfs = 0;
    for (const glm::vec3& ref : kRefs) {
        for (int i = 0; i < kSamples; ++i) {
            // Toward the light (next-event estimation).
            const LightLiSample s = sample_li(light, ref, rng.next_vec2());
            if (s.valid()) {
                ++li_valid;
                EXPECT_EQ(s.is_delta, is_delta(type)) << what << ": sample_li's delta flag";
                const float pdf = pdf_li(light, ref, s.wi);
                if (is_delta(type)) {
                    EXPECT_EQ(pdf, 0.0f) << what << ": a delta light's pdf_li";
                }
                Ray ray;
                ray.origin = ref;
                ray.direction = s.wi;
                Hit hit;
                const bool hits = scene.intersect(ray, hit);
                if (type == LightType::Area) {
                    // Rays can hit it: the ray toward the sample finds the light's surface.
                    area_pdfs += pdf > 0.0f ? 1 : 0;
                    area_hits += hits && scene.light_of_hit(hit) == 0 ? 1 : 0;
                } else {
                    EXPECT_FALSE(hits && scene.light_of_hit(hit) != kInvalidId)
                        << what << ": a ray hit a light that has no surface";
                }
                const glm::vec3 seen = escaped_radiance(light, s.wi);
                if (type == LightType::Infinite) {
                    EXPECT_TRUE(near(seen, s.radiance, 1e-4f * glm::length(s.radiance)))
                        << what << ": an escaping ray sees what sample_li brought";
                } else {
                    EXPECT_EQ(seen, glm::vec3(0.0f)) << what << ": only Infinite lights are seen";
                }
            }
        }
    }
    for (int i = 0; i < kSamples; ++i) {
        // Leaving the light (paths that start there).
        const LightLeSample s = sample_le(light, sphere, rng.next_vec2(), rng.next_vec2());
        if (!s.valid()) continue;
        ++le_valid;
        EXPECT_EQ(s.delta_position, type == LightType::DeltaPosition) << what;
        EXPECT_EQ(s.delta_direction, type == LightType::DeltaDirection) << what;
        const glm::vec3 n = surface_normal(light, s.origin);
        if (type == LightType::Area) {
            // The ray leaves the surface on the side of its normal, which is the surface's
            // (either side of a two-sided light).
            EXPECT_NEAR(glm::length(n), 1.0f, 1e-5f) << what;
            EXPECT_TRUE(near(s.normal, n, 1e-4f) || near(s.normal, -n, 1e-4f))
                << what << ": surface_normal disagrees with sample_le's normal";
            EXPECT_GE(glm::dot(s.normal, s.direction), 0.0f) << what;
        } else {
            EXPECT_EQ(n, glm::vec3(0.0f)) << what << ": only a surface has a normal";
        }
        if (b.infinite) {
            // A sun's bounds hold the direction toward it; an environment's, everything.
            if (b.cone) {
                EXPECT_GE(glm::dot(-s.direction, b.axis), b.cos_cone - kRounding) << what;
            }
            continue;
        }
        EXPECT_LE(glm::length(s.origin - b.centre), b.radius) << what << ": origin outside bounds";
        if (b.cone) {
            EXPECT_GE(glm::dot(s.direction, b.axis), b.cos_cone - kRounding)
                << what << ": emitted outside the bounds' cone";
        }
    }
    EXPECT_GE(li_valid, kSamples) << what;
    EXPECT_GT(le_valid, kSamples / 2) << what;
    if (type == LightType::Area) {
        EXPECT_GE(area_pdfs, li_valid - 2) << what << ": sample_li's directions have pdf_li 0";
        EXPECT_GE(area_hits, li_valid * 99 / 100) << what << ": rays do not hit the light";
    }

    // preprocess: a light at infinity takes the scene's radius, and its power (what it
    // sends through the scene's disk) grows as its area; other lights keep theirs.
    Light small = light, large = light;
    preprocess(small, SceneSummary{{glm::vec3(0.0f), 2.0f}, {}});
    preprocess(large, SceneSummary{{glm::vec3(0.0f), 4.0f}, {}});
    Light as_scene = light;
    preprocess(as_scene, SceneSummary{sphere, {}});
    EXPECT_EQ(power(as_scene), power(light)) << what << ": Scene::commit preprocessed it";
    const glm::vec3 ratio = is_at_infinity(type) ? glm::vec3(4.0f) : glm::vec3(1.0f);
    EXPECT_TRUE(near(power(large), ratio * power(small), 1e-5f * glm::length(power(large))))
        << what << ": power after preprocess";
}

template <class Kind>
void check_kind(const std::string& name) {
    const std::vector<Kind> all = examples(std::type_identity<Kind>{});
    ASSERT_FALSE(all.empty()) << name;
    for (std::size_t i = 0; i < all.size(); ++i) {
        const std::string what = name + " example " + std::to_string(i);
        const Scene scene = scene_with(all[i]);
        ASSERT_TRUE(std::holds_alternative<Kind>(scene.lights()[0].source)) << what;
        check(scene, what);
    }
}

template <std::size_t... I>
void check_every_kind(std::index_sequence<I...> /*kinds*/) {
    (check_kind<std::variant_alternative_t<I, LightSource>>("LightSource alternative " +
                                                            std::to_string(I)),
     ...);
}

TEST(LightKinds, TypeNormalBoundsAndPreprocessAgreeWithSampling) {
    check_every_kind(std::make_index_sequence<std::variant_size_v<LightSource>>());
}

TEST(LightKinds, EveryLightTypeIsSomeKindsAnswer) {
    // The examples cover each LightType, so each branch of check() above runs.
    bool seen[4] = {};
    const auto note = [&](const auto& kind_examples) {
        for (const auto& l : kind_examples) seen[int(l.type())] = true;
    };
    note(examples(std::type_identity<PointLight>{}));
    note(examples(std::type_identity<SphereLight>{}));
    note(examples(std::type_identity<DirectionalLight>{}));
    note(examples(std::type_identity<EnvironmentLight>{}));
    EXPECT_TRUE(seen[int(LightType::DeltaPosition)]);
    EXPECT_TRUE(seen[int(LightType::DeltaDirection)]);
    EXPECT_TRUE(seen[int(LightType::Area)]);
    EXPECT_TRUE(seen[int(LightType::Infinite)]);
}

TEST(LightKinds, SphereLightPreprocessFindsTheSpheresThatBuryIt) {
    // A sphere light half inside an opaque ball: preprocess gives it cuts; without opaque
    // spheres it has none.
    Light light{SphereLight{{{0.0f, 1.0f, 0.0f}, 0.5f}, glm::vec3(1.0f)}, kInvalidId};
    const DoubleSphere ball(glm::dvec3(0.0, 0.0, 0.0), 1.0);
    preprocess(light, SceneSummary{{glm::vec3(0.0f), 2.0f}, {&ball, 1}});
    EXPECT_NE(std::get<SphereLight>(light.source).cuts, nullptr);
    preprocess(light, SceneSummary{{glm::vec3(0.0f), 2.0f}, {}});
    EXPECT_EQ(std::get<SphereLight>(light.source).cuts, nullptr);
}

}  // namespace
}  // namespace librt
