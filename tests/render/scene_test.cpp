#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <random>
#include <string>
#include <variant>
#include <vector>

namespace librt {
using librt::testing::error_of;

namespace {

// Two triangles forming the square [x0, x1] x [y0, y1] at height z, facing +z.
TriangleMesh quad_z(float x0, float y0, float x1, float y1, float z) {
    TriangleMesh m;
    m.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

TEST(Scene, QueriesBeforeCommitThrow) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    scene.add_sphere({{0, 0, 0}, 1}, m);
    Hit hit;
    Ray ray{{0, 0, 5}, {0, 0, -1}};
    EXPECT_NE(error_of([&] { (void)scene.intersect(ray, hit); }).find("commit"), std::string::npos);
    EXPECT_THROW((void)scene.occluded(ray), Error);
    scene.commit();
    EXPECT_TRUE(scene.intersect(ray, hit));
    // Adding anything un-commits.
    scene.add_sphere({{3, 0, 0}, 1}, m);
    EXPECT_FALSE(scene.committed());
    EXPECT_THROW((void)scene.intersect(ray, hit), Error);
    scene.commit();
    EXPECT_TRUE(scene.occluded(ray));
}

TEST(Scene, EmptySceneHitsNothing) {
    Scene scene;
    scene.commit();
    Hit hit;
    EXPECT_FALSE(scene.intersect(Ray{{0, 0, 0}, {0, 0, -1}}, hit));
    EXPECT_FALSE(scene.occluded(Ray{{0, 0, 0}, {0, 0, -1}}));
    EXPECT_TRUE(scene.bounds().empty());
}

TEST(Scene, RejectsBadInput) {
    Scene scene;
    EXPECT_NE(error_of([&] {
                  scene.add_sphere({{0, 0, 0}, 1}, 0);
              }).find("material id 0"),
              std::string::npos);
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    EXPECT_NE(error_of([&] {
                  scene.add_sphere({{0, 0, 0}, -2}, m);
              }).find("radius = -2"),
              std::string::npos);
    EXPECT_THROW(scene.add_sphere({{NAN, 0, 0}, 1}, m), Error);
    TriangleMesh bad = quad_z(0, 0, 1, 1, 0);
    bad.triangles.push_back({0, 1, 7});
    EXPECT_NE(error_of([&] { scene.add_mesh(bad, m); }).find("out of range"), std::string::npos);
    EXPECT_THROW(scene.add_triangle({{0, 0, 0}, {1, 0, 0}, {0, INFINITY, 0}}, m), Error);
    Material textured = Material::diffuse(glm::vec3(1.0f));
    textured.albedo_texture = 3;
    EXPECT_NE(error_of([&] { scene.add_material(textured); }).find("albedo_texture = 3"),
              std::string::npos);
    EXPECT_THROW(scene.add_point_light({{0, 0, 0}, {-1, 0, 0}}), Error);
    EXPECT_THROW(scene.add_sphere_light({{{0, 0, 0}, 0.0f}, {1, 1, 1}}), Error);
}

// Brute-force closest hit over the scene's raw primitives, for comparison.
struct Reference {
    std::vector<Sphere> spheres;                                // object ids 0..n-1
    std::vector<std::pair<Triangle, std::uint32_t>> triangles;  // with object ids

    bool closest(const Ray& ray, float& t, std::uint32_t& object) const {
        t = ray.t_max;
        object = kInvalidId;
        for (std::size_t i = 0; i < spheres.size(); ++i) {
            Ray r = ray;
            r.t_max = t;
            if (const auto h = intersect(spheres[i], r)) {
                t = *h;
                object = std::uint32_t(i);
            }
        }
        for (const auto& [tri, id] : triangles) {
            Ray r = ray;
            r.t_max = t;
            if (const auto h = intersect(tri, r)) {
                t = h->t;
                object = id;
            }
        }
        return object != kInvalidId;
    }
};

TEST(Scene, ClosestHitAmongOverlappingSpheresAndMeshAgreesWithBruteForce) {
    Scene scene;
    Reference ref;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const std::vector<Sphere> spheres = {{{0, 0, 0}, 1.0f},
                                         {{0.5f, 0, -0.5f}, 1.0f},
                                         {{-0.3f, 0.4f, 0.2f}, 0.5f},
                                         {{0, -1000, 0}, 998.5f}};
    for (const Sphere& s : spheres) {
        scene.add_sphere(s, m);
        ref.spheres.push_back(s);
    }
    // A mesh cutting through the spheres: a tilted fan of triangles.
    TriangleMesh mesh;
    std::mt19937 rng(7);
    std::uniform_real_distribution<float> U(-1.5f, 1.5f);
    for (int i = 0; i < 40; ++i) {
        const glm::vec3 c(U(rng), U(rng), U(rng));
        const auto base = std::uint32_t(mesh.positions.size());
        mesh.positions.insert(mesh.positions.end(), {c, c + glm::vec3(0.4f, U(rng) * 0.2f, 0.1f),
                                                     c + glm::vec3(0.1f, 0.3f, U(rng) * 0.3f)});
        mesh.triangles.emplace_back(base, base + 1, base + 2);
    }
    const auto mesh_id = scene.add_mesh(mesh, m);
    for (std::size_t i = 0; i < mesh.triangle_count(); ++i)
        ref.triangles.emplace_back(mesh.triangle(i), mesh_id);
    scene.commit();
    EXPECT_EQ(scene.object_count(), 5u);

    std::uniform_real_distribution<float> dir(-1.0f, 1.0f);
    int hits = 0, mesh_hits = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray ray;
        ray.origin = glm::vec3(dir(rng), dir(rng), dir(rng)) * 4.0f;
        ray.direction = glm::normalize(glm::vec3(dir(rng), dir(rng), dir(rng)) - 0.3f * ray.origin);
        if (i % 3 == 0) ray.t_max = 2.0f;  // bounded segments too
        float t_ref;
        std::uint32_t obj_ref;
        const bool ref_hit = ref.closest(ray, t_ref, obj_ref);
        Hit hit;
        const bool got = scene.intersect(ray, hit);
        ASSERT_EQ(got, ref_hit) << "ray " << i;
        ASSERT_EQ(scene.occluded(ray), ref_hit) << "ray " << i;
        if (!got) continue;
        ++hits;
        mesh_hits += hit.object_id == mesh_id;
        EXPECT_EQ(hit.object_id, obj_ref) << "ray " << i;
        EXPECT_NEAR(hit.t, t_ref, 1e-5f * std::max(1.0f, t_ref)) << "ray " << i;
        EXPECT_NEAR(glm::length(hit.geometric_normal), 1.0f, 1e-5f);
        EXPECT_NEAR(glm::length(hit.point - ray.at(hit.t)), 0.0f, 1e-4f);
    }
    EXPECT_GT(hits, 1000);
    EXPECT_GT(mesh_hits, 50);
}

// Past 16 objects the top level is the SAH Bvh instead of a flat list: same answers.
TEST(Scene, ManyObjectsThroughTheTopLevelBvhAgreeWithBruteForce) {
    Scene scene;
    Reference ref;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    std::mt19937 rng(21);
    std::uniform_real_distribution<float> U(-5.0f, 5.0f);
    for (int i = 0; i < 60; ++i) {
        const Sphere s{{U(rng), U(rng), U(rng)}, 0.2f + 0.1f * std::fabs(U(rng))};
        scene.add_sphere(s, m);
        ref.spheres.push_back(s);
    }
    scene.add_sphere({{0, -1000, 0}, 994.0f}, m);  // a huge one, as in the room
    ref.spheres.push_back({{0, -1000, 0}, 994.0f});
    for (int k = 0; k < 3; ++k) {
        TriangleMesh mesh = quad_z(U(rng), U(rng), 6.0f, 6.0f, U(rng));
        const auto id = scene.add_mesh(mesh, m);
        for (std::size_t i = 0; i < mesh.triangle_count(); ++i)
            ref.triangles.emplace_back(mesh.triangle(i), id);
    }
    scene.commit();
    int hits = 0;
    for (int i = 0; i < 4000; ++i) {
        Ray ray;
        ray.origin = {U(rng), U(rng), U(rng)};
        ray.direction = glm::normalize(glm::vec3(U(rng), U(rng), U(rng)));
        if (i % 3 == 0) ray.t_max = std::fabs(U(rng));
        float t_ref;
        std::uint32_t obj_ref;
        const bool ref_hit = ref.closest(ray, t_ref, obj_ref);
        Hit hit;
        ASSERT_EQ(scene.intersect(ray, hit), ref_hit) << "ray " << i;
        ASSERT_EQ(scene.occluded(ray), ref_hit) << "ray " << i;
        if (!ref_hit) continue;
        ++hits;
        EXPECT_EQ(hit.object_id, obj_ref) << "ray " << i;
        EXPECT_NEAR(hit.t, t_ref, 1e-5f * std::max(1.0f, t_ref)) << "ray " << i;
    }
    EXPECT_GT(hits, 1000);
}

TEST(Scene, OccludedAgreesWithIntersectOnRandomRays) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    scene.add_sphere({{0, 0, 0}, 1.0f}, m);
    scene.add_sphere({{2, 0, 0}, 0.5f}, m);
    scene.add_mesh(quad_z(-2, -2, 2, 2, -1.5f), m);
    scene.add_triangle({{-1, 1.5f, 0}, {1, 1.5f, 0}, {0, 1.5f, 1}}, m);
    scene.add_sphere_light({{{0, 3, 0}, 0.5f}, glm::vec3(1.0f)});
    scene.commit();
    std::mt19937 rng(11);
    std::uniform_real_distribution<float> U(-3.0f, 3.0f);
    int agree_hits = 0;
    for (int i = 0; i < 5000; ++i) {
        Ray ray;
        ray.origin = {U(rng), U(rng), U(rng)};
        ray.direction = glm::normalize(glm::vec3(U(rng), U(rng), U(rng)));
        ray.t_max = (i % 2) ? INFINITY : std::fabs(U(rng));
        Hit hit;
        const bool h = scene.intersect(ray, hit);
        ASSERT_EQ(scene.occluded(ray), h) << "ray " << i;
        agree_hits += h;
        if (h) {
            // Ignoring the object hit first: occluded iff something else is on the segment.
            bool other = false;
            Hit h2;
            Ray probe = ray;
            for (int k = 0; k < 8 && scene.intersect(probe, h2); ++k) {
                if (h2.object_id != hit.object_id) {
                    other = true;
                    break;
                }
                probe.t_min =
                    std::nextafter(h2.t, INFINITY);  // past this hit of the ignored object
            }
            EXPECT_EQ(scene.occluded(ray, hit.object_id), other) << "ray " << i;
        }
    }
    EXPECT_GT(agree_hits, 500);
}

TEST(Scene, HitRecordOfTrianglesAndSpheres) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    TriangleMesh mesh = quad_z(0, 0, 2, 2, 0);
    // Bent vertex normals and uvs.
    mesh.normals = {glm::normalize(glm::vec3(-1, 0, 1)), glm::normalize(glm::vec3(1, 0, 1)),
                    glm::normalize(glm::vec3(1, 0, 1)), glm::normalize(glm::vec3(-1, 0, 1))};
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const auto quad = scene.add_mesh(mesh, m);
    const auto ball = scene.add_sphere({{10, 0, 0}, 2.0f}, m);
    scene.commit();

    Hit hit;
    // From above, at x = 1.5, y = 0.5: triangle 0, normal +z.
    ASSERT_TRUE(scene.intersect(Ray{{1.5f, 0.5f, 3}, {0, 0, -1}}, hit));
    EXPECT_EQ(hit.object_id, quad);
    EXPECT_EQ(hit.primitive_id, 0u);
    EXPECT_FLOAT_EQ(hit.t, 3.0f);
    EXPECT_NEAR(hit.geometric_normal.z, 1.0f, 1e-6f);
    EXPECT_NEAR(hit.uv.x, 0.75f, 1e-6f);
    EXPECT_NEAR(hit.uv.y, 0.25f, 1e-6f);
    // Shading normal: interpolated, leaning +x at x = 1.5.
    const glm::vec3 expect_ns = glm::normalize(0.25f * mesh.normals[0] + 0.75f * mesh.normals[1]);
    EXPECT_NEAR(glm::dot(hit.shading_normal, expect_ns), 1.0f, 1e-6f);
    // From below: the geometric normal still follows the winding (+z).
    ASSERT_TRUE(scene.intersect(Ray{{0.5f, 1.5f, -3}, {0, 0, 1}}, hit));
    EXPECT_EQ(hit.primitive_id, 1u);
    EXPECT_NEAR(hit.geometric_normal.z, 1.0f, 1e-6f);
    // Sphere: outward normal, also from inside; uv with v growing toward +y.
    ASSERT_TRUE(scene.intersect(Ray{{10, 5, 0}, {0, -1, 0}}, hit));
    EXPECT_EQ(hit.object_id, ball);
    EXPECT_NEAR(hit.geometric_normal.y, 1.0f, 1e-6f);
    EXPECT_NEAR(hit.uv.y, 1.0f, 1e-6f);
    ASSERT_TRUE(scene.intersect(Ray{{10, 0, 0}, {0, -1, 0}}, hit));
    EXPECT_NEAR(hit.geometric_normal.y, -1.0f, 1e-6f);
    EXPECT_NEAR(hit.uv.y, 0.0f, 1e-6f);
    EXPECT_EQ(hit.shading_normal, hit.geometric_normal);
    // Bounds cover both objects.
    EXPECT_TRUE(scene.bounds().contains({0, 0, 0}));
    EXPECT_TRUE(scene.bounds().contains({12, 2, 2}));
}

TEST(Scene, TexturedAlbedo) {
    Scene scene;
    // 2 x 1 texture: left red, right green (linear values).
    const auto tex = scene.add_texture(ImageTexture(2, 1, {{1, 0, 0}, {0, 1, 0}}));
    Material m = Material::diffuse(glm::vec3(0.5f));
    m.albedo_texture = tex;
    const auto mat = scene.add_material(m);
    TriangleMesh mesh = quad_z(0, 0, 1, 1, 0);
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    scene.add_mesh(mesh, mat);
    scene.commit();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0.25f, 0.5f, 1}, {0, 0, -1}}, hit));
    EXPECT_NEAR(scene.albedo(hit).x, 1.0f, 1e-6f);  // texel centre of the left texel
    ASSERT_TRUE(scene.intersect(Ray{{0.75f, 0.5f, 1}, {0, 0, -1}}, hit));
    EXPECT_NEAR(scene.albedo(hit).y, 1.0f, 1e-6f);
}

TEST(Scene, SphereLightIsAnEmissiveObject) {
    Scene scene;
    const SphereLight light{{{0, 5, 0}, 1.0f}, {2, 3, 4}};
    const auto id = scene.add_sphere_light(light);
    scene.add_point_light({{1, 1, 1}, {1, 1, 1}});
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 2u);
    ASSERT_TRUE(std::holds_alternative<SphereLight>(scene.lights()[0].source));
    ASSERT_TRUE(std::holds_alternative<PointLight>(scene.lights()[1].source));
    EXPECT_EQ(scene.lights()[0].object, id);
    EXPECT_EQ(scene.lights()[1].object, kInvalidId);
    EXPECT_EQ(scene.light_of_object(id), 0u);
    EXPECT_EQ(scene.light_of_object(id + 1), kInvalidId);
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0, 0, 0}, {0, 1, 0}}, hit));
    EXPECT_EQ(hit.object_id, id);
    EXPECT_EQ(scene.material(hit).kind, MaterialKind::Emissive);
    EXPECT_EQ(scene.material(hit).emission, light.radiance);
}

TEST(Scene, UnsampledEmittersAreAnyEmissionButTheSphereLights) {
    Scene scene;
    const auto diffuse = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    scene.add_sphere({{0, 0, 0}, 1.0f}, diffuse);
    scene.add_sphere_light({{{0, 5, 0}, 1.0f}, {2, 3, 4}});
    scene.commit();
    EXPECT_FALSE(scene.has_unsampled_emitters()) << "the light's own emission is sampled";

    Material glowing = Material::diffuse(glm::vec3(0.5f));
    glowing.emission = glm::vec3(0.1f);
    scene.add_triangle({{0, 0, 3}, {1, 0, 3}, {0, 1, 3}}, scene.add_material(glowing));
    scene.commit();
    // Issue 12 item 6: emissive triangles are lights now, so their emission is sampled.
    EXPECT_FALSE(scene.has_unsampled_emitters()) << "a loose emissive triangle is a light";
    scene.add_sphere({{0, 0, 9}, 1.0f}, scene.add_material(glowing));
    scene.commit();
    EXPECT_TRUE(scene.has_unsampled_emitters()) << "an emissive sphere that is no light";

    // Per-triangle materials: one emissive triangle among diffuse ones.
    Scene mtl_scene;
    const auto matte = mtl_scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const auto lamp = mtl_scene.add_material(Material::emissive(glm::vec3(4.0f)));
    const TriangleMesh mesh = quad_z(0, 0, 1, 1, 0);
    mtl_scene.add_mesh(mesh, std::vector<std::uint32_t>{matte, matte});
    mtl_scene.commit();
    EXPECT_FALSE(mtl_scene.has_unsampled_emitters());
    mtl_scene.add_mesh(mesh, std::vector<std::uint32_t>{matte, lamp});
    mtl_scene.commit();
    EXPECT_FALSE(mtl_scene.has_unsampled_emitters()) << "the emissive triangle is a light";
    EXPECT_EQ(mtl_scene.lights().size(), 1u);
}

TEST(Scene, OffsetScalesWithPositionAndFollowsDirection) {
    const glm::vec3 n(0, 1, 0);
    const glm::vec3 p1(1, 0, 0), p1000(1000, 0, 0);
    const glm::vec3 up = offset_ray_origin(p1, n, {0.3f, 0.8f, 0});
    const glm::vec3 down = offset_ray_origin(p1, n, {0.3f, -0.8f, 0});
    EXPECT_GT(up.y, 0.0f);
    EXPECT_LT(down.y, 0.0f);
    EXPECT_FLOAT_EQ(offset_ray_origin(p1, n, n).y, kRayOffsetAbsolute + kRayOffsetRelative);
    EXPECT_FLOAT_EQ(offset_ray_origin(p1000, n, n).y,
                    kRayOffsetAbsolute + 1000.0f * kRayOffsetRelative);
    EXPECT_GT(ray_offset_scale(glm::vec3(0.0f)), 0.0f);
}

// Rays leaving random points of the report's huge wall spheres and of a mesh must not
// hit the surface they leave (self-intersection), whatever their direction.
TEST(Scene, SpawnedRaysDoNotSelfIntersect) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const auto floor = scene.add_sphere({{0, -1000, 0}, 990}, m);
    const auto wall = scene.add_sphere({{0, 0, -1050}, 940}, m);
    const auto plate = scene.add_mesh(quad_z(-30, -9, 30, 30, -60), m);  // in front of the wall
    scene.commit();
    std::mt19937 rng(3);
    std::uniform_real_distribution<float> U(0.0f, 1.0f);
    int tested = 0;
    for (int i = 0; i < 20000; ++i) {
        // A camera-like ray from inside the room toward a random direction.
        Ray ray;
        ray.origin = {60 * U(rng) - 30, 40 * U(rng) - 5, 50 * U(rng) - 25};
        ray.direction = glm::normalize(glm::vec3(U(rng) - 0.5f, U(rng) - 0.9f, U(rng) - 0.9f));
        Hit hit;
        if (!scene.intersect(ray, hit)) continue;
        ++tested;
        // Leave the surface on the side the ray came from, at any angle (grazing included).
        const glm::vec3 ng = glm::dot(ray.direction, hit.geometric_normal) < 0.0f
                                 ? hit.geometric_normal
                                 : -hit.geometric_normal;
        const Frame frame = Frame::from_normal(ng);
        const float cos_t = (i % 4 == 0) ? 1e-4f * U(rng) : U(rng);
        const float phi = 6.2831853f * U(rng);
        const float sin_t = std::sqrt(1.0f - cos_t * cos_t);
        const glm::vec3 w =
            glm::normalize(frame.to_world({sin_t * std::cos(phi), sin_t * std::sin(phi), cos_t}));
        // Rounding can tip a near-tangent w below the surface: that is a ray going in, which
        // the integrators never spawn from a reflection.
        if (!(glm::dot(w, ng) > 0.0f)) continue;
        const Ray out = spawn_ray(hit, w);
        Hit next;
        if (scene.intersect(out, next)) {
            // Spheres seen from outside and a plane cannot be re-hit by a leaving ray.
            ASSERT_NE(next.object_id, hit.object_id)
                << "ray " << i << " o " << ray.origin.x << "," << ray.origin.y << ","
                << ray.origin.z << " d " << ray.direction.x << "," << ray.direction.y << ","
                << ray.direction.z << " p " << hit.point.x << "," << hit.point.y << ","
                << hit.point.z << " ng " << hit.geometric_normal.x << "," << hit.geometric_normal.y
                << "," << hit.geometric_normal.z << " w " << w.x << "," << w.y << "," << w.z
                << " t " << hit.t << " self-hit object " << hit.object_id << " at t = " << next.t;
        }
    }
    EXPECT_GT(tested, 10000);
    (void)floor;
    (void)wall;
    (void)plate;
}

}  // namespace
}  // namespace librt
