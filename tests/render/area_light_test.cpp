// Area lights (issue 12 items 6, 7, 10): emissive meshes, quads and disks are sampled, and
// the MIS path tracer equals the brute-force one on a small scene; a quad's irradiance
// equals Lambert's closed form for a polygon; hidden emitters and a sphere light seen
// from inside.

#include "light_scene_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include <array>
#include <cmath>
#include <vector>

namespace librt {
namespace {

using testing::add_floor_and_ball;
using testing::expect_mis_equals_brute;
using testing::irradiance_by_sampling;
using testing::lambert_polygon_irradiance;
using testing::Pinhole;
using testing::region;
using testing::render_stats;

TEST(AreaLights, EmissiveMeshTrianglesBecomeLightsWithPerTriangleMapping) {
    Scene scene;
    const auto matte = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const auto lamp = scene.add_material(Material::emissive(glm::vec3(3.0f)));
    TriangleMesh mesh;
    mesh.positions = {{0, 1, 0}, {1, 1, 0}, {1, 1, 1}, {0, 1, 1}};
    mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
    const std::uint32_t obj = scene.add_mesh(mesh, std::vector<std::uint32_t>{matte, lamp});
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 1u);
    ASSERT_TRUE(std::holds_alternative<TriangleLight>(scene.lights()[0].source));
    Hit hit;
    hit.object_id = obj;
    hit.primitive_id = 1;
    EXPECT_EQ(scene.light_of_hit(hit), 0u);
    hit.primitive_id = 0;
    EXPECT_EQ(scene.light_of_hit(hit), kInvalidId);
    // Power of a two-sided triangle of area 1/2: L pi A 2.
    EXPECT_NEAR(power(scene.lights()[0]).x, 3.0f * kPi, 1e-4f);
    // Adding a light after commit() keeps the added lights first and remakes the rest.
    scene.add_point_light(PointLight::from_power({0, 3, 0}, 1.0f));
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 2u);
    EXPECT_TRUE(std::holds_alternative<PointLight>(scene.lights()[0].source));
    hit.primitive_id = 1;
    EXPECT_EQ(scene.light_of_hit(hit), 1u);
}

TEST(AreaLights, EmissiveMeshMisEqualsBruteForce) {
    Scene scene;
    add_floor_and_ball(scene);
    // A ceiling panel of two emissive triangles facing down, as a mesh of its own.
    TriangleMesh panel;
    panel.positions = {
        {-0.6f, 2.2f, -0.6f}, {0.6f, 2.2f, -0.6f}, {0.6f, 2.2f, 0.6f}, {-0.6f, 2.2f, 0.6f}};
    panel.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(panel, scene.add_material(Material::emissive(glm::vec3(4.0f, 3.0f, 2.0f))));
    scene.commit();
    EXPECT_EQ(scene.lights().size(), 2u);
    EXPECT_FALSE(scene.has_unsampled_emitters());
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 256, "emissive mesh");
}

TEST(AreaLights, EmissiveInstancesAreLightsPlacedByTheirMatrix) {
    Scene scene;
    add_floor_and_ball(scene);
    // A unit panel facing +y, placed twice: turned face down (x mirrored by the half turn
    // about z), scaled by 1.2 and lifted to y = 2.2, and a second, smaller copy beside it.
    TriangleMesh panel;
    panel.positions = {{-0.5f, 0, -0.5f}, {-0.5f, 0, 0.5f}, {0.5f, 0, 0.5f}, {0.5f, 0, -0.5f}};
    panel.triangles = {{0, 1, 2}, {0, 2, 3}};
    const std::uint32_t proto = scene.add_mesh_prototype(panel);
    const auto lamp = scene.add_material(Material::emissive(glm::vec3(4.0f, 3.0f, 2.0f)));
    const glm::mat4 down = glm::rotate(glm::mat4(1.0f), kPi, glm::vec3(0, 0, 1));
    const glm::mat4 m1 = glm::translate(glm::mat4(1.0f), {0.0f, 2.2f, 0.0f}) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(1.2f)) * down;
    const glm::mat4 m2 = glm::translate(glm::mat4(1.0f), {-1.2f, 2.0f, 0.8f}) *
                         glm::scale(glm::mat4(1.0f), glm::vec3(0.5f)) * down;
    const std::uint32_t first = scene.add_instance(proto, m1, lamp);
    scene.add_instance(proto, m2, lamp);
    scene.commit();
    ASSERT_EQ(scene.lights().size(), 4u);  // two triangles per instance
    EXPECT_FALSE(scene.has_unsampled_emitters());
    // The lights are the instance's world triangles: those of the baked copy.
    Hit hit;
    hit.object_id = first;
    hit.primitive_id = 1;
    const std::uint32_t li = scene.light_of_hit(hit);
    ASSERT_NE(li, kInvalidId);
    const auto& tl = std::get<TriangleLight>(scene.lights()[li].source);
    const glm::uvec3& t = panel.triangles[1];
    const glm::vec3 want[3] = {glm::vec3(m1 * glm::vec4(panel.positions[t.x], 1.0f)),
                               glm::vec3(m1 * glm::vec4(panel.positions[t.y], 1.0f)),
                               glm::vec3(m1 * glm::vec4(panel.positions[t.z], 1.0f))};
    const glm::vec3 got[3] = {tl.p0, tl.p1, tl.p2};
    for (int i = 0; i < 3; ++i) EXPECT_LT(glm::length(got[i] - want[i]), 1e-5f) << i;
    // Power of two-sided triangles: L pi A 2, area (1.2^2 + 0.5^2) / 2 per triangle.
    glm::vec3 total(0.0f);
    for (const Light& l : scene.lights()) total += power(l);
    EXPECT_NEAR(total.x, 4.0f * kPi * 2.0f * (1.44f + 0.25f), 1e-3f);
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 256, "emissive instances");
}

TEST(AreaLights, QuadMisEqualsBruteForce) {
    Scene scene;
    add_floor_and_ball(scene);
    // One-sided, facing down (edge0 x edge1 = -y): the floor is lit, its back is dark.
    scene.add_quad_light({{-0.5f, 2.2f, -0.5f}, {1.0f, 0, 0}, {0, 0, 1.0f}, glm::vec3(5.0f)});
    scene.commit();
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 256, "quad");
    expect_mis_equals_brute(scene, testing::side_camera(), 32, 256, "quad, side view");
}

TEST(AreaLights, OneSidedQuadFacingAwayLightsNothing) {
    Scene scene;
    add_floor_and_ball(scene);
    scene.add_quad_light({{-0.5f, 2.2f, -0.5f}, {0, 0, 1.0f}, {1.0f, 0, 0}, glm::vec3(5.0f)});
    scene.commit();
    PathTracerSettings s;
    s.max_depth = 3;
    PathTracer mis(s);
    BruteForcePathTracer brute(s);
    for (Integrator* integrator : std::array<Integrator*, 2>{&mis, &brute}) {
        const auto img = render_stats(scene, *integrator, testing::top_camera(), 8, 3);
        const auto r = region(img, 0, 0, img.width, img.height);
        EXPECT_EQ(r.mean.x, 0.0) << "a one-sided light facing up lights the floor below";
    }
}

TEST(AreaLights, DiskMisEqualsBruteForce) {
    Scene scene;
    add_floor_and_ball(scene);
    scene.add_disk_light({{0.0f, 2.0f, 0.0f}, {0.3f, -1.0f, 0.0f}, 0.6f, glm::vec3(3.0f), true});
    scene.commit();
    expect_mis_equals_brute(scene, testing::top_camera(), 32, 256, "two-sided disk");
    expect_mis_equals_brute(scene, testing::side_camera(), 32, 256, "two-sided disk, side");
}

TEST(AreaLights, QuadIrradianceMatchesLambertPolygonFormula) {
    const QuadLight quad{
        {-0.4f, 1.5f, -0.7f}, {1.1f, 0.1f, 0.0f}, {0.0f, 0.2f, 0.9f}, glm::vec3(2.0f), true};
    Light light{quad, kInvalidId};
    const glm::vec3 a = quad.corner, b = a + quad.edge0, c = b + quad.edge1, d = a + quad.edge1;
    struct Case {
        glm::vec3 p, n;
    };
    for (const Case& k : {Case{{0, 0, 0}, {0, 1, 0}}, Case{{0.5f, 0.2f, -0.3f}, {0.3f, 0.9f, 0.1f}},
                          Case{{-1.0f, 0.5f, 0.5f}, {0.6f, 0.8f, 0.0f}}}) {
        const glm::vec3 n = glm::normalize(k.n);
        const double expected =
            lambert_polygon_irradiance({glm::dvec3(a), glm::dvec3(b), glm::dvec3(c), glm::dvec3(d)},
                                       glm::dvec3(k.p), glm::dvec3(n), 2.0);
        const auto e = irradiance_by_sampling(light, k.p, n, 200000, 5);
        EXPECT_GT(expected, 0.05);
        EXPECT_NEAR(e.mean.x, expected, 5.0 * e.se.x + 1e-6) << "at " << k.p.x << "," << k.p.y;
    }
}

TEST(AreaLights, DiskAndTriangleIrradianceMatchLambertPolygonFormula) {
    const DiskLight disk{{0.2f, 1.3f, -0.1f}, {0.2f, -1.0f, 0.1f}, 0.5f, glm::vec3(1.5f), false};
    std::vector<glm::dvec3> corners;
    for (int i = 0; i < kDiskLightSides; ++i) corners.emplace_back(disk_light_corner(disk, i));
    const glm::vec3 p(0.1f, 0.0f, 0.3f), n(0.0f, 1.0f, 0.0f);
    const auto e = irradiance_by_sampling(Light{disk, kInvalidId}, p, n, 100000, 6);
    EXPECT_NEAR(e.mean.x, lambert_polygon_irradiance(corners, glm::dvec3(p), glm::dvec3(n), 1.5),
                5.0 * e.se.x);
    TriangleLight tri;
    tri.p0 = {-1, 1, -1};
    tri.p1 = {1, 1.2f, -1};
    tri.p2 = {0, 0.9f, 1};
    tri.radiance = glm::vec3(3.0f);
    const auto t = irradiance_by_sampling(Light{tri, kInvalidId}, p, n, 100000, 7);
    EXPECT_NEAR(
        t.mean.x,
        lambert_polygon_irradiance({glm::dvec3(tri.p0), glm::dvec3(tri.p1), glm::dvec3(tri.p2)},
                                   glm::dvec3(p), glm::dvec3(n), 3.0),
        5.0 * t.se.x);
}

TEST(LightVisibility, HiddenSphereLightLetsCameraRaysThroughButStillLights) {
    Scene scene;
    add_floor_and_ball(scene);
    // On the line from the eye to the ball's centre: the ball is behind the light.
    const glm::vec3 eye(0.0f, 1.0f, 3.5f), ball(0.3f, 0.5f, 0.2f);
    const std::uint32_t obj =
        scene.add_sphere_light({{eye + 0.6f * (ball - eye), 0.3f}, glm::vec3(8.0f)});
    scene.commit();
    Pinhole cam;
    cam.width = cam.height = 1;
    cam.eye = eye;
    cam.forward = glm::normalize(ball - eye);
    cam.up = glm::normalize(glm::cross(glm::cross(cam.forward, glm::vec3(0, 1, 0)), cam.forward));
    DirectLighting direct;
    Sampler sampler(0, 0, 0, 1);
    const glm::vec3 seen = direct.li(scene, cam.ray(0, 0), sampler);
    EXPECT_FLOAT_EQ(seen.x, 8.0f) << "visible: the camera sees the light's radiance";
    EXPECT_FALSE(scene.may_hide_objects()) << "nothing hidden yet: the path loop skips the lookup";
    scene.set_camera_visible(obj, false);
    EXPECT_TRUE(scene.may_hide_objects());
    const glm::vec3 hidden = direct.li(scene, cam.ray(0, 0), sampler);
    EXPECT_LT(hidden.x, 8.0f);
    EXPECT_GT(hidden.x, 0.0f) << "behind the hidden light: the ball, lit by that light";
    // Still lights the scene as before, and MIS still equals brute force.
    expect_mis_equals_brute(scene, testing::side_camera(), 32, 256, "hidden sphere light");
}

TEST(LightVisibility, SphereLightSeenFromInsideIsAnEmitterOnBothSides) {
    // Inside a sphere light of radiance L, a small diffuse quad of albedo a sees the
    // light's inner surface over its whole hemisphere: its radiance is exactly a L.
    Scene scene;
    const auto matte = scene.add_material(Material::diffuse(glm::vec3(0.6f)));
    TriangleMesh q;
    q.positions = {{-0.2f, 0, -0.2f}, {-0.2f, 0, 0.2f}, {0.2f, 0, 0.2f}, {0.2f, 0, -0.2f}};
    q.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(q, matte);
    scene.add_sphere_light({{{0.0f, 0.0f, 0.0f}, 2.0f}, glm::vec3(2.0f)});
    scene.commit();
    Pinhole cam;
    cam.eye = {0, 1, 0};
    cam.forward = {0, -1, 0};
    cam.up = {0, 0, -1};
    cam.fov_degrees = 10.0f;
    cam.width = cam.height = 2;
    PathTracerSettings s;
    s.max_depth = 2;
    PathTracer mis(s);
    BruteForcePathTracer brute(s);
    const auto a = region(render_stats(scene, mis, cam, 256, 4), 0, 0, 2, 2);
    const auto b = region(render_stats(scene, brute, cam, 64, 5), 0, 0, 2, 2);
    EXPECT_NEAR(a.mean.x, 1.2, 5.0 * std::sqrt(a.se2.x) + 1e-5);
    EXPECT_NEAR(b.mean.x, 1.2, 1e-4) << "every BSDF ray finds the light: no variance";
}

}  // namespace
}  // namespace librt
