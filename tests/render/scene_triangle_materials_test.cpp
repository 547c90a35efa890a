// Scene::add_mesh with one scene material per triangle (what obj/obj_materials.h builds on).

#include "robustness/robustness_util.h"

#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

namespace librt {
namespace {

using librt::testing::error_of;
using librt::testing::has;

TEST(SceneTriangleMaterials, EachTriangleGetsItsMaterial) {
    Scene scene;
    const auto red = scene.add_material(Material::diffuse({1, 0, 0}));
    const auto green = scene.add_material(Material::diffuse({0, 1, 0}));
    TriangleMesh mesh;  // two triangles side by side along x, facing +z
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {2, 1, 0}};
    mesh.triangles = {{0, 1, 2}, {3, 4, 5}};
    const auto id = scene.add_mesh(mesh, std::vector<std::uint32_t>{green, red});
    scene.commit();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0.2f, 0.2f, 1}, {0, 0, -1}}, hit));
    EXPECT_EQ(hit.object_id, id);
    EXPECT_EQ(scene.material_id(hit), green);
    ASSERT_TRUE(scene.intersect(Ray{{2.2f, 0.2f, 1}, {0, 0, -1}}, hit));
    EXPECT_EQ(scene.material_id(hit), red);
}

TEST(SceneTriangleMaterials, BadIdsOrCountsAddNothing) {
    Scene scene;
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    TriangleMesh mesh;
    mesh.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
    mesh.triangles = {{0, 1, 2}};
    std::string msg = error_of([&] { (void)scene.add_mesh(mesh, std::vector<std::uint32_t>{}); });
    EXPECT_TRUE(has(msg, "0 material ids for 1 triangles")) << msg;
    msg = error_of([&] { (void)scene.add_mesh(mesh, std::vector<std::uint32_t>{grey, grey}); });
    EXPECT_TRUE(has(msg, "2 material ids for 1 triangles")) << msg;
    msg = error_of([&] { (void)scene.add_mesh(mesh, std::vector<std::uint32_t>{7}); });
    EXPECT_TRUE(has(msg, "material id 7")) << msg;
    mesh.positions[2].z = NAN;
    msg = error_of([&] { (void)scene.add_mesh(mesh, std::vector<std::uint32_t>{grey}); });
    EXPECT_TRUE(has(msg, "position 2 is not finite")) << msg;
    EXPECT_EQ(scene.object_count(), 0u);
}

}  // namespace
}  // namespace librt
