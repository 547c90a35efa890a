// MTL -> scene material mapping and texture loading (obj/obj_materials.h, io/texture_io.h):
// the policy, texture de-duplication, and warnings returned instead of printed.

#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/io/texture_io.h>
#include <librt/obj/obj_materials.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace librt {
namespace {

using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;

// Two triangles forming the square [x0, x1] x [y0, y1] at height z, facing +z.
TriangleMesh quad_z(float x0, float y0, float x1, float y1, float z) {
    TriangleMesh m;
    m.positions = {{x0, y0, z}, {x1, y0, z}, {x1, y1, z}, {x0, y1, z}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    return m;
}

// A 1 x 1 binary PPM of the given sRGB colour.
std::filesystem::path write_ppm(const ScratchDir& dir, const std::string& name, unsigned char r,
                                unsigned char g, unsigned char b) {
    return dir.write(name, std::string("P6\n1 1\n255\n") + char(r) + char(g) + char(b));
}

TEST(MtlMaterials, PolicyMapsEachMtlCase) {
    MeshMaterial mtl;
    mtl.name = "plain";
    mtl.diffuse = {0.2f, 0.4f, 0.6f};
    Material m = material_from_mtl(mtl);
    EXPECT_EQ(m.kind, MaterialKind::Diffuse);
    EXPECT_EQ(m.albedo, mtl.diffuse);
    EXPECT_EQ(m.albedo_texture, -1);
    mtl.diffuse_texture = "/nonexistent/librt/never_read.png";  // the policy reads no file
    EXPECT_EQ(material_from_mtl(mtl).albedo_texture, -1);

    MeshMaterial lamp = mtl;
    lamp.emission = {0.0f, 2.0f, 0.0f};
    lamp.illum = 4;  // emission wins over everything
    m = material_from_mtl(lamp);
    EXPECT_EQ(m.kind, MaterialKind::Emissive);
    EXPECT_EQ(m.emission, lamp.emission);

    for (const int illum : {4, 6, 7}) {
        MeshMaterial glass = mtl;
        glass.illum = illum;
        glass.ior = 1.33f;
        m = material_from_mtl(glass);
        EXPECT_EQ(m.kind, MaterialKind::Dielectric) << illum;
        EXPECT_FLOAT_EQ(m.ior, 1.33f);
    }
    MeshMaterial see_through = mtl;
    see_through.dissolve = 0.5f;
    see_through.ior = 0.0f;  // no Ni: glass of 1.5
    m = material_from_mtl(see_through);
    EXPECT_EQ(m.kind, MaterialKind::Dielectric);
    EXPECT_FLOAT_EQ(m.ior, 1.5f);

    for (const int illum : {3, 5}) {
        MeshMaterial chrome = mtl;
        chrome.illum = illum;
        m = material_from_mtl(chrome);
        EXPECT_EQ(m.kind, MaterialKind::Mirror) << illum;
        EXPECT_EQ(m.albedo, glm::vec3(1.0f)) << "Ks 0: an untinted mirror";
        chrome.specular = {0.9f, 0.8f, 0.7f};
        EXPECT_EQ(material_from_mtl(chrome).albedo, chrome.specular);
    }
    MeshMaterial white_ks = mtl;
    white_ks.specular = glm::vec3(1.0f);
    EXPECT_EQ(material_from_mtl(white_ks).kind, MaterialKind::Mirror);

    MeshMaterial bright = mtl;
    bright.name = "too_bright";
    bright.diffuse = {1.5f, 0.0f, 0.0f};
    const std::string msg = error_of([&] { (void)material_from_mtl(bright); });
    EXPECT_TRUE(has(msg, "MTL material 'too_bright'")) << msg;
}

TEST(MtlMaterials, PerTriangleMtlMaterials) {
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.1f, 0.2f, 0.3f)));
    // Five triangles side by side along x, each its own material (last one: no valid id).
    TriangleMesh mesh;
    for (std::uint32_t i = 0; i < 5; ++i) {
        const float x = float(i) * 2.0f;
        mesh.positions.insert(mesh.positions.end(), {{x, 0, 0}, {x + 1, 0, 0}, {x, 1, 0}});
        mesh.triangles.emplace_back(3 * i, 3 * i + 1, 3 * i + 2);
    }
    MeshMaterial red;
    red.name = "red";
    red.diffuse = {0.9f, 0.1f, 0.1f};
    red.diffuse_texture = "/nonexistent/librt/texture.png";  // warned about, Kd kept
    MeshMaterial lamp;
    lamp.name = "lamp";
    lamp.emission = {5, 5, 5};
    MeshMaterial glass;
    glass.name = "glass";
    glass.illum = 4;
    glass.ior = 1.33f;
    MeshMaterial chrome;
    chrome.name = "chrome";
    chrome.illum = 3;
    chrome.specular = glm::vec3(1.0f);
    mesh.materials = {red, lamp, glass, chrome};
    mesh.material_ids = {0, 1, 2, 3, 99};
    EXPECT_NE(
        error_of([&] { (void)add_mesh_with_mtl(scene, mesh, fallback); }).find("material id 99"),
        std::string::npos);
    EXPECT_EQ(scene.object_count(), 0u);
    EXPECT_EQ(scene.material_count(), 1u) << "a bad mesh adds no material";
    mesh.material_ids.back() = 0;
    const MtlMeshResult added = add_mesh_with_mtl(scene, mesh, fallback);
    const auto obj = added.object_id;
    ASSERT_EQ(added.warnings.size(), 1u);
    EXPECT_TRUE(has(added.warnings[0], "red")) << added.warnings[0];
    EXPECT_TRUE(has(added.warnings[0], "/nonexistent/librt/texture.png")) << added.warnings[0];
    // The same mesh with one material: its MTL ignored.
    TriangleMesh moved = mesh;
    for (glm::vec3& p : moved.positions) p.y += 5.0f;
    const auto uniform = scene.add_mesh(moved, fallback);
    // Without material ids: the fallback throughout, and no material added.
    TriangleMesh bare = moved;
    for (glm::vec3& p : bare.positions) p.y += 5.0f;
    bare.material_ids.clear();
    const std::size_t materials_before = scene.material_count();
    const MtlMeshResult bare_added = add_mesh_with_mtl(scene, bare, fallback);
    const auto bare_id = bare_added.object_id;
    EXPECT_TRUE(bare_added.warnings.empty());
    EXPECT_EQ(scene.material_count(), materials_before);
    scene.commit();

    auto material_at = [&](float x, float y) {
        Hit hit;
        EXPECT_TRUE(scene.intersect(Ray{{x, y, 1}, {0, 0, -1}}, hit));
        return std::pair{hit.object_id, scene.material(hit)};
    };
    auto [o0, m0] = material_at(0.25f, 0.25f);
    EXPECT_EQ(o0, obj);
    EXPECT_EQ(m0.kind, MaterialKind::Diffuse);
    EXPECT_EQ(m0.albedo, red.diffuse);
    EXPECT_EQ(m0.albedo_texture, -1);
    auto [o1, m1] = material_at(2.25f, 0.25f);
    EXPECT_EQ(m1.kind, MaterialKind::Emissive);
    EXPECT_EQ(m1.emission, glm::vec3(5.0f));
    auto [o2, m2] = material_at(4.25f, 0.25f);
    EXPECT_EQ(m2.kind, MaterialKind::Dielectric);
    EXPECT_FLOAT_EQ(m2.ior, 1.33f);
    auto [o3, m3] = material_at(6.25f, 0.25f);
    EXPECT_EQ(m3.kind, MaterialKind::Mirror);
    auto [o4, m4] = material_at(8.25f, 0.25f);
    EXPECT_EQ(m4.albedo, red.diffuse);
    auto [o5, m5] = material_at(4.25f, 5.25f);
    EXPECT_EQ(o5, uniform);
    EXPECT_EQ(m5.kind, MaterialKind::Diffuse);
    EXPECT_EQ(m5.albedo, glm::vec3(0.1f, 0.2f, 0.3f));
    auto [o6, m6] = material_at(2.25f, 10.25f);
    EXPECT_EQ(o6, bare_id);
    EXPECT_EQ(m6.kind, MaterialKind::Diffuse);
    EXPECT_EQ(m6.albedo, glm::vec3(0.1f, 0.2f, 0.3f));
}

TEST(MtlMaterials, MtlTexturesAreLoadedOncePerPath) {
    ScratchDir dir;
    const auto path = write_ppm(dir, "white.ppm", 255, 255, 255);
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    TriangleMesh mesh = quad_z(0, 0, 1, 1, 0);
    MeshMaterial a, b;
    a.name = "a";
    b.name = "b";
    a.diffuse_texture = b.diffuse_texture = path.string();
    mesh.materials = {a, b};
    mesh.material_ids = {0, 1};
    EXPECT_TRUE(add_mesh_with_mtl(scene, mesh, fallback).warnings.empty());
    EXPECT_EQ(scene.texture_count(), 1u);
    scene.commit();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0.7f, 0.2f, 1}, {0, 0, -1}}, hit));
    EXPECT_EQ(scene.material(hit).albedo_texture, 0);
    EXPECT_NEAR(scene.albedo(hit).x, 1.0f, 1e-6f);
}

TEST(MtlMaterials, SharedTextureIdsLoadEachFileOncePerScene) {
    ScratchDir dir;
    const auto white = write_ppm(dir, "white.ppm", 255, 255, 255);
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    TriangleMesh mesh = quad_z(0, 0, 1, 1, 0);
    MeshMaterial painted;
    painted.name = "painted";
    painted.diffuse_texture = white.string();
    MeshMaterial broken;
    broken.name = "broken";
    broken.diffuse_texture = (dir.path() / "absent.png").string();
    mesh.materials = {painted, broken};
    mesh.material_ids = {0, 1};
    // Without a shared map every call loads its own copy (and warns again).
    EXPECT_EQ(add_mesh_with_mtl(scene, mesh, fallback).warnings.size(), 1u);
    EXPECT_EQ(add_mesh_with_mtl(scene, mesh, fallback).warnings.size(), 1u);
    EXPECT_EQ(scene.texture_count(), 2u);
    // With one: the second mesh reuses the first one's texture and its failure is not
    // retried (nor warned about twice).
    TextureIdsByPath textures;
    const MtlMeshResult first = add_mesh_with_mtl(scene, mesh, fallback, &textures);
    const MtlMeshResult second = add_mesh_with_mtl(scene, mesh, fallback, &textures);
    EXPECT_EQ(first.warnings.size(), 1u);
    EXPECT_TRUE(second.warnings.empty());
    EXPECT_EQ(scene.texture_count(), 3u);
    ASSERT_EQ(textures.size(), 2u);
    EXPECT_EQ(textures.at(white.string()), 2);
    EXPECT_EQ(textures.at(broken.diffuse_texture), -1);
}

// A texture that fails to load is a warning in the returned list, never on stderr, and
// the material keeps its Kd.
TEST(MtlMaterials, FailedTextureIsAReturnedWarningAndKeepsKd) {
    ScratchDir dir;
    const auto junk = dir.write("junk.png", "this is not an image");
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    TriangleMesh mesh = quad_z(0, 0, 1, 1, 0);
    mesh.uvs = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    MeshMaterial painted;
    painted.name = "painted";
    painted.diffuse = {0.1f, 0.2f, 0.3f};
    painted.diffuse_texture = junk.string();
    mesh.materials = {painted};
    mesh.material_ids = {0, 0};
    ::testing::internal::CaptureStderr();
    ::testing::internal::CaptureStdout();
    const MtlMeshResult added = add_mesh_with_mtl(scene, mesh, fallback);
    const std::string out = ::testing::internal::GetCapturedStdout();
    const std::string err = ::testing::internal::GetCapturedStderr();
    EXPECT_EQ(err, "");
    EXPECT_EQ(out, "");
    ASSERT_EQ(added.warnings.size(), 1u);
    EXPECT_TRUE(has(added.warnings[0], "MTL material 'painted'")) << added.warnings[0];
    EXPECT_TRUE(has(added.warnings[0], "cannot load texture")) << added.warnings[0];
    EXPECT_TRUE(has(added.warnings[0], "junk.png")) << added.warnings[0];
    EXPECT_TRUE(has(added.warnings[0], "Kd")) << added.warnings[0];
    EXPECT_EQ(scene.texture_count(), 0u);
    scene.commit();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, hit));
    EXPECT_EQ(hit.object_id, added.object_id);
    EXPECT_EQ(scene.material(hit).albedo_texture, -1);
    EXPECT_EQ(scene.albedo(hit), glm::vec3(0.1f, 0.2f, 0.3f));
}

TEST(MtlMaterials, UnknownFallbackAddsNothing) {
    Scene scene;
    TriangleMesh mesh = quad_z(0, 0, 1, 1, 0);
    mesh.materials.resize(1);
    mesh.material_ids = {0, 0};
    const std::string msg = error_of([&] { (void)add_mesh_with_mtl(scene, mesh, 3); });
    EXPECT_TRUE(has(msg, "material id 3")) << msg;
    EXPECT_EQ(scene.material_count(), 0u);
    EXPECT_EQ(scene.object_count(), 0u);
}

TEST(TextureIo, LoadsSrgbAsLinearAndRefusesHugeHeaders) {
    ScratchDir dir;
    const ImageTexture grey = load_texture(write_ppm(dir, "grey.ppm", 0, 128, 255));
    ASSERT_EQ(grey.width(), 1);
    ASSERT_EQ(grey.height(), 1);
    EXPECT_FLOAT_EQ(grey.texel(0, 0).x, 0.0f);
    EXPECT_NEAR(grey.texel(0, 0).y, srgb_to_linear(128.0f / 255.0f), 1e-6f);
    EXPECT_NEAR(grey.texel(0, 0).z, 1.0f, 1e-6f);
    // One texel over the limit, claimed by the header: refused before decoding.
    const std::uint64_t side = std::uint64_t{1} << 13u;  // 8192^2 = kMaxTextureTexels
    static_assert((std::uint64_t{1} << 13u) * (std::uint64_t{1} << 13u) == kMaxTextureTexels);
    const std::string over =
        "P6\n" + std::to_string(side) + " " + std::to_string(side + 1) + "\n255\n";
    const std::string msg = error_of([&] { (void)load_texture(dir.write("over.ppm", over)); });
    EXPECT_TRUE(has(msg, "more than the limit")) << msg;
}

}  // namespace
}  // namespace librt
