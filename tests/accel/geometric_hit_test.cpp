// The geometric-only closest-hit query (GeometricHit: t, ids, normal from the BVH leaf)
// against the finished query it shortens: the same hits and normals bit for bit.

#include "ray_sets.h"
#include "test_support.h"

#include <librt/accel/top_level.h>
#include <librt/core/error.h>
#include <librt/geometry/procedural.h>
#include <librt/material/material.h>
#include <librt/obj/obj.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace librt {
namespace {

/// Expects `g` (the geometric query) to be `h` (the finished one) bit for bit; returns
/// whether the query hit.
template <class Query>
bool expect_same_hit(const Query& query, const Ray& ray, const std::string& where) {
    Hit h;
    GeometricHit g;
    const bool found = query.intersect(ray, h);
    EXPECT_EQ(query.intersect(ray, g), found) << where;
    if (!found) {
        EXPECT_EQ(g.object_id, kInvalidId) << where << ": a miss leaves the hit alone";
        return false;
    }
    EXPECT_EQ(g.t, h.t) << where;
    EXPECT_EQ(g.primitive_id, h.primitive_id) << where;
    EXPECT_EQ(g.object_id, h.object_id) << where;
    EXPECT_EQ(g.instance_id, h.instance_id) << where;
    for (int c = 0; c < 3; ++c) EXPECT_EQ(g.geometric_normal[c], h.geometric_normal[c]) << where;
    EXPECT_NEAR(glm::length(g.geometric_normal), 1.0f, 1e-6f) << where;
    return true;
}

/// Random rays through [-r, r]^3, some with a t_min or t_max cutting into the scene.
std::vector<Ray> random_rays(std::size_t count, float r, std::uint32_t seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> U(-r, r);
    std::vector<Ray> rays(count);
    for (std::size_t i = 0; i < count; ++i) {
        const glm::vec3 o{U(rng), U(rng), U(rng)};
        const glm::vec3 target{U(rng) / 3, U(rng) / 3, U(rng) / 3};
        rays[i] = Ray{o, target - o, i % 5 == 0 ? std::fabs(U(rng)) / r : 0.0f,
                      i % 7 == 0 ? std::fabs(U(rng)) / r : std::numeric_limits<float>::infinity()};
    }
    return rays;
}

TEST(GeometricHit, BunnySceneMatchesTheFinishedHit) {
    LIBRT_REQUIRE_DATA_FILE(path, "stanford-bunny.obj");
    TriangleMesh bunny = load_obj(path);
    const BBox box = bunny.bounds();
    Scene scene;
    scene.add_mesh(std::move(bunny), scene.add_material(Material::diffuse(glm::vec3(0.5f))));
    scene.commit();
    std::size_t hits = 0;
    const std::vector<Ray> rays = testing::incoherent_rays(box, 100'000, 7);
    for (std::size_t i = 0; i < rays.size(); ++i)
        hits += expect_same_hit(scene, rays[i], "ray " + std::to_string(i));
    EXPECT_GT(hits, 50'000u);  // the incoherent set hits the bunny ~61 % of the time
}

// Instances (a mirroring and a non-uniform scale among them), plain meshes and spheres,
// through the flat list (up to 16 objects) and through the top-level BVH (more).
TEST(GeometricHit, InstancedSceneMatchesTheFinishedHit) {
    for (const int copies : {2, 12}) {
        TopLevel top;
        const std::uint32_t ico = top.add_prototype(make_icosphere({0, 0, 0}, 0.6f, 2));
        const std::uint32_t pot = top.add_prototype(make_teapot(3));
        std::mt19937 rng(5);
        std::uniform_real_distribution<float> U(-1.0f, 1.0f);
        for (int k = 0; k < copies; ++k) {
            const glm::vec3 at{3 * U(rng), 3 * U(rng), 3 * U(rng)};
            glm::mat4 m = glm::translate(glm::mat4(1.0f), at);
            m = glm::rotate(m, 3 * U(rng), glm::normalize(glm::vec3(U(rng), U(rng), 1.0f)));
            m = glm::scale(m, glm::vec3(0.5f + std::fabs(U(rng)), 0.3f, k % 3 == 0 ? -0.4f : 0.7f));
            top.add_instance(k % 2 ? ico : pot, m);
        }
        top.add_mesh(ico);
        top.add_sphere(Sphere{{2.0f, -1.0f, 0.5f}, 0.8f});
        top.add_sphere(glm::dvec3(-2.0, 1.0, -0.5), 0.5, false);
        top.build();
        std::size_t hits = 0, instance_hits = 0, sphere_hits = 0;
        const std::vector<Ray> rays = random_rays(40'000, 6.0f, 9);
        for (std::size_t i = 0; i < rays.size(); ++i) {
            if (!expect_same_hit(top, rays[i],
                                 std::to_string(copies) + " copies, ray " + std::to_string(i)))
                continue;
            ++hits;
            GeometricHit g;
            (void)top.intersect(rays[i], g);
            instance_hits += g.instance_id != kInvalidId;
            sphere_hits += top.kind(g.object_id) == ObjectKind::Sphere;
        }
        EXPECT_GT(instance_hits, 150u * std::size_t(copies)) << copies;
        EXPECT_GT(sphere_hits, 500u) << copies;
        EXPECT_GT(hits - instance_hits - sphere_hits, 500u) << copies;  // the plain mesh
    }
}

// The queries that skip the box visit: a flat list of spheres only (two touching, so
// that some rays take the visit for a tie) and a lone mesh or instance.
TEST(GeometricHit, SpheresAndLoneObjectsMatchTheFinishedHit) {
    TopLevel spheres;
    spheres.add_sphere(Sphere{{0.0f, 0.0f, 0.0f}, 1.0f});
    spheres.add_sphere(Sphere{{2.0f, 0.0f, 0.0f}, 1.0f});  // touches the first at (1, 0, 0)
    spheres.add_sphere(Sphere{{0.0f, -1e3f - 2.0f, 0.0f}, 1e3f});
    spheres.build();
    std::size_t hits = 0;
    const std::vector<Ray> rays = random_rays(20'000, 4.0f, 3);
    for (std::size_t i = 0; i < rays.size(); ++i)
        hits += expect_same_hit(spheres, rays[i], "spheres, ray " + std::to_string(i));
    for (int y = -20; y <= 20; ++y)  // rays through the touching point
        hits += expect_same_hit(spheres, Ray{{1.0f, 0.001f * float(y), 5.0f}, {0, 0, -1}},
                                "touching point " + std::to_string(y));
    EXPECT_GT(hits, 5'000u);

    const glm::mat4 mirror = glm::scale(glm::mat4(1.0f), glm::vec3(-1.0f, 0.5f, 2.0f));
    for (const bool instance : {false, true}) {
        TopLevel one;
        const std::uint32_t proto = one.add_prototype(make_teapot(3));
        if (instance)
            one.add_instance(proto, mirror);
        else
            one.add_mesh(proto);
        one.build();
        std::size_t lone_hits = 0;
        for (std::size_t i = 0; i < rays.size(); ++i)
            lone_hits += expect_same_hit(one, rays[i], "lone, ray " + std::to_string(i));
        EXPECT_GT(lone_hits, 1'000u) << instance;
        GeometricHit g;
        EXPECT_FALSE(one.intersect(Ray{{std::nanf(""), 0, 0}, {1, 0, 0}}, g));
    }
    TopLevel unbuilt;
    unbuilt.add_sphere(Sphere{{0, 0, 0}, 1});
    GeometricHit g;
    EXPECT_THROW((void)unbuilt.intersect(Ray{{0, 0, 5}, {0, 0, -1}}, g), Error);
}

// A scene with a partly covered surface (alpha blend: each ray passes it or not by its
// hash) over a floor: the query goes through the finished one there, past the holes.
TEST(GeometricHit, SceneWithCutOutsMatchesTheFinishedHit) {
    Scene scene;
    scene.add_mesh(make_box({-3, -1, -3}, {3, 0, 3}),
                   scene.add_material(Material::diffuse(glm::vec3(0.5f))));
    Material veil = Material::diffuse(glm::vec3(0.8f));
    veil.alpha = 0.5f;
    veil.alpha_blend = true;
    scene.add_mesh(make_box({-1, 0, -1}, {1, 2, 1}), scene.add_material(veil));
    scene.add_sphere(Sphere{{2.0f, 1.0f, 2.0f}, 0.7f}, 0);
    GeometricHit g;
    EXPECT_THROW((void)scene.intersect(Ray{{0, 5, 0}, {0, -1, 0}}, g), Error);
    scene.commit();
    std::size_t hits = 0, veil_hits = 0;
    const std::vector<Ray> rays = random_rays(20'000, 5.0f, 4);
    for (std::size_t i = 0; i < rays.size(); ++i) {
        if (!expect_same_hit(scene, rays[i], "ray " + std::to_string(i))) continue;
        ++hits;
        (void)scene.intersect(rays[i], g);
        veil_hits += g.object_id == 1;
    }
    EXPECT_GT(hits, 5'000u);
    EXPECT_GT(veil_hits, 500u);  // some rays stop on the veil, others pass it
}

}  // namespace
}  // namespace librt
