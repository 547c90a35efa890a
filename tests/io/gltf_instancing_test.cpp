// Issue 42 items 3 and 7, on files the tests write: EXT_mesh_gpu_instancing's per-instance
// TRANSLATION / ROTATION / SCALE, the choice of a scene (GltfLoadOptions::scene,
// SceneFileOptions::scene), KHR_materials_variants (variant), and the units of punctual
// lights (SceneFileOptions::light_units).

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"

#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/loader/scene_file.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <string>
#include <variant>
#include <vector>

using namespace librt;
using librt::testing::GltfBuilder;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

constexpr int kGrid = 5;  // 5 x 5 x 5 = 125 instances, as the SimpleInstancing sample
constexpr int kInstances = kGrid * kGrid * kGrid;

/// Instance i's translation, angle about +y and scale: each different.
glm::vec3 translation_of(int i) {
    return {float(i % kGrid) * 3.0f, float(i / kGrid % kGrid) * 3.0f, float(i / 25) * 3.0f};
}
float angle_of(int i) { return 0.05f * float(i); }
glm::vec3 scale_of(int i) { return {1.0f + 0.01f * float(i), 0.5f, 2.0f}; }

/// One triangle (mesh 0) placed by node 0 (translated by (0, 100, 0)) through
/// EXT_mesh_gpu_instancing with all three attributes, 125 instances.
GltfBuilder instanced() {
    GltfBuilder b = lt::one_triangle();
    std::vector<float> t, r, s;
    for (int i = 0; i < kInstances; ++i) {
        const glm::vec3 ti = translation_of(i), si = scale_of(i);
        t.insert(t.end(), {ti.x, ti.y, ti.z});
        // A rotation by a about +y: (x, y, z, w) = (0, sin(a/2), 0, cos(a/2)).
        r.insert(r.end(), {0.0f, std::sin(angle_of(i) / 2), 0.0f, std::cos(angle_of(i) / 2)});
        s.insert(s.end(), {si.x, si.y, si.z});
    }
    const int ta = b.add_accessor(t, lt::kFloat, "VEC3", kInstances);
    const int ra = b.add_accessor(r, lt::kFloat, "VEC4", kInstances);
    const int sa = b.add_accessor(s, lt::kFloat, "VEC3", kInstances);
    b.doc["extensionsUsed"] = {"EXT_mesh_gpu_instancing"};
    b.doc["extensionsRequired"] = {"EXT_mesh_gpu_instancing"};
    b.doc["nodes"][0]["translation"] = {0, 100, 0};
    b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"] = {
        {"TRANSLATION", ta}, {"ROTATION", ra}, {"SCALE", sa}};
    return b;
}

/// The attributes object of node 0's EXT_mesh_gpu_instancing.
json& attributes(GltfBuilder& b) {
    return b.doc["nodes"][0]["extensions"]["EXT_mesh_gpu_instancing"]["attributes"];
}

GltfScene load(const ScratchDir& dir, const GltfBuilder& b, const GltfLoadOptions& o = {}) {
    const fs::path p = dir.path() / "file.gltf";
    lt::write_file(p, b.gltf());
    return load_gltf(p, o);
}

/// The message of the librt::Error loading `b` throws.
std::string load_error(const GltfBuilder& b, const GltfLoadOptions& o = {}) {
    ScratchDir dir;
    return lt::error_of([&] { (void)load(dir, b, o); });
}

}  // namespace

TEST(GltfGpuInstancing, OneHundredTwentyFiveInstancesWithTheirTransforms) {
    ScratchDir dir;
    const GltfScene s = load(dir, instanced());
    ASSERT_EQ(s.instances.size(), std::size_t(kInstances));
    EXPECT_EQ(s.meshes.size(), 1u);
    for (int i = 0; i < kInstances; ++i) {
        SCOPED_TRACE(i);
        const GltfInstance& inst = s.instances[std::size_t(i)];
        EXPECT_EQ(inst.mesh, 0);
        EXPECT_EQ(inst.node, 0);
        EXPECT_EQ(inst.gpu_instance, i);
        // The vertex (1, 0, 0): scaled to (sx, 0, 0), turned by a about +y to
        // sx (cos a, 0, -sin a), moved by the instance's translation, then by the node's.
        const glm::vec3 p = glm::vec3(inst.world * glm::vec4(1.0f, 0.0f, 0.0f, 1.0f));
        const float a = angle_of(i), sx = scale_of(i).x;
        const glm::vec3 want =
            translation_of(i) + glm::vec3(0, 100, 0) + sx * glm::vec3(std::cos(a), 0, -std::sin(a));
        EXPECT_NEAR(p.x, want.x, 1e-4f);
        EXPECT_NEAR(p.y, want.y, 1e-4f);
        EXPECT_NEAR(p.z, want.z, 1e-4f);
        // (0, 1, 0) scaled by sy = 0.5, unaffected by the turn about y.
        const glm::vec3 q = glm::vec3(inst.world * glm::vec4(0.0f, 1.0f, 0.0f, 1.0f));
        EXPECT_NEAR(q.y, translation_of(i).y + 100.0f + 0.5f, 1e-4f);
        EXPECT_NEAR(q.x, translation_of(i).x, 1e-4f);
    }
    EXPECT_TRUE(s.warnings.empty()) << lt::joined(s.warnings);
}

TEST(GltfGpuInstancing, TheSceneStoresTheMeshOnceAndPlacesItPerInstance) {
    ScratchDir dir;
    const fs::path p = dir.path() / "instanced.glb";
    lt::write_file(p, instanced().glb());
    LoadedScene loaded = load_scene_file(p);
    EXPECT_EQ(loaded.triangles_stored, 1u);
    EXPECT_EQ(loaded.triangles_placed, std::size_t(kInstances));
    loaded.scene.commit();
    // Each instance's triangle where its transform puts it: corners (0, 0, 0), (1, 0, 0) and
    // (0, 1, 0) scaled, turned by a about +y and moved, predicted by hand. A ray along its
    // normal, from 1 unit away (the instances are 3 apart), hits its centre at t = 1.
    for (const int i : {0, 7, 124}) {
        SCOPED_TRACE(i);
        const float a = angle_of(i);
        const glm::vec3 origin = translation_of(i) + glm::vec3(0, 100, 0);
        const glm::vec3 c0 = origin;
        const glm::vec3 c1 = origin + scale_of(i).x * glm::vec3(std::cos(a), 0, -std::sin(a));
        const glm::vec3 c2 = origin + glm::vec3(0, scale_of(i).y, 0);
        const glm::vec3 n = glm::normalize(glm::cross(c1 - c0, c2 - c0));
        const glm::vec3 centre = (c0 + c1 + c2) / 3.0f;
        Hit hit;
        ASSERT_TRUE(loaded.scene.intersect(Ray(centre + n, -n), hit));
        EXPECT_NEAR(hit.t, 1.0f, 1e-4f);
        EXPECT_NEAR(glm::length(hit.point - centre), 0.0f, 1e-4f);
    }
}

TEST(GltfGpuInstancing, AnyAttributeAloneAndQuantisedRotations) {
    ScratchDir dir;
    // SCALE alone: 3 instances, translated only by the node.
    {
        GltfBuilder b = instanced();
        const int sa =
            b.add_accessor(std::vector<float>{1, 1, 1, 2, 2, 2, 3, 3, 3}, lt::kFloat, "VEC3", 3);
        attributes(b) = {{"SCALE", sa}};
        const GltfScene s = load(dir, b);
        ASSERT_EQ(s.instances.size(), 3u);
        const glm::vec3 p = glm::vec3(s.instances[2].world * glm::vec4(1, 1, 1, 1));
        EXPECT_NEAR(p.x, 3.0f, 1e-6f);
        EXPECT_NEAR(p.y, 103.0f, 1e-5f);
    }
    // ROTATION as normalised shorts (KHR_mesh_quantization): a quarter turn about +z, with
    // components 23170 / 32767 = 0.7071 (renormalised to a unit quaternion).
    {
        GltfBuilder b = instanced();
        const std::vector<std::int16_t> q = {0, 0, 23170, 23170, 0, 0, 0, 32767};
        const int ra = b.add_accessor(q, lt::kI16, "VEC4", 2, /*normalized=*/true);
        attributes(b) = {{"ROTATION", ra}};
        const GltfScene s = load(dir, b);
        ASSERT_EQ(s.instances.size(), 2u);
        // (1, 0, 0) turned a quarter about +z: (0, 1, 0); the identity leaves it.
        const glm::vec3 p = glm::vec3(s.instances[0].world * glm::vec4(1, 0, 0, 1));
        EXPECT_NEAR(p.x, 0.0f, 1e-4f);
        EXPECT_NEAR(p.y, 101.0f, 1e-4f);
        const glm::vec3 p1 = glm::vec3(s.instances[1].world * glm::vec4(1, 0, 0, 1));
        EXPECT_NEAR(p1.x, 1.0f, 1e-6f);
    }
}

TEST(GltfGpuInstancing, BadAccessorsAreErrorsNamingTheJsonPath) {
    const std::string where = "nodes[0].extensions.EXT_mesh_gpu_instancing.attributes.";
    // Wrong type: a VEC4 TRANSLATION.
    {
        GltfBuilder b = instanced();
        attributes(b)["TRANSLATION"] = attributes(b)["ROTATION"];
        const std::string e = load_error(b);
        EXPECT_TRUE(lt::has(e, where + "TRANSLATION: accessors[")) << e;
        EXPECT_TRUE(lt::has(e, ".type: must be VEC3")) << e;
    }
    // Wrong component type: a ROTATION of bytes that are not normalised.
    {
        GltfBuilder b = instanced();
        const std::vector<std::int8_t> q = {0, 0, 0, 127};
        attributes(b)["ROTATION"] = b.add_accessor(q, lt::kI8, "VEC4", 1);
        const std::string e = load_error(b);
        EXPECT_TRUE(lt::has(e, where + "ROTATION: accessors[")) << e;
        EXPECT_TRUE(lt::has(e, ".componentType: 5120: must be FLOAT, or normalized BYTE or SHORT"))
            << e;
    }
    // Count mismatch: 124 scales for 125 translations.
    {
        GltfBuilder b = instanced();
        attributes(b)["SCALE"] =
            b.add_accessor(std::vector<float>(124 * 3, 1.0f), lt::kFloat, "VEC3", 124);
        const std::string e = load_error(b);
        EXPECT_TRUE(lt::has(e, where + "SCALE: accessors[")) << e;
        EXPECT_TRUE(lt::has(e, "has 124 elements, ROTATION's has 125")) << e;
    }
    // An accessor that does not exist.
    {
        GltfBuilder b = instanced();
        attributes(b)["SCALE"] = 99;
        const std::string e = load_error(b);
        EXPECT_TRUE(lt::has(e, where + "SCALE: accessor 99 does not exist")) << e;
    }
    // An accessor whose elements run past its buffer view.
    {
        GltfBuilder b = instanced();
        const int sa = attributes(b)["SCALE"];
        b.doc["accessors"][sa]["count"] = 126;
        b.doc["accessors"][int(attributes(b)["TRANSLATION"])]["count"] = 126;
        b.doc["accessors"][int(attributes(b)["ROTATION"])]["count"] = 126;
        const std::string e = load_error(b);
        EXPECT_TRUE(lt::has(e, where + "TRANSLATION: accessors[")) << e;
        EXPECT_TRUE(lt::has(e, "do not fit in bufferViews[")) << e;
    }
    // An index beyond int (tinygltf would wrap it).
    {
        GltfBuilder b = instanced();
        attributes(b)["SCALE"] = 4294967296ull;
        const std::string e = load_error(b);
        EXPECT_TRUE(lt::has(e, where + "SCALE: 4294967296 is too large")) << e;
    }
    // A zero quaternion; no attribute at all; no mesh to instance.
    {
        GltfBuilder b = instanced();
        attributes(b)["ROTATION"] = b.add_accessor(std::vector<float>(kInstances * 4, 0.0f),
                                                   lt::kFloat, "VEC4", kInstances);
        EXPECT_TRUE(lt::has(load_error(b), where + "ROTATION: element 0 is a zero quaternion"));
        attributes(b) = {{"_ID", 0}};
        EXPECT_TRUE(
            lt::has(load_error(b), "attributes: has none of TRANSLATION, ROTATION and SCALE"));
        b = instanced();
        b.doc["nodes"][0].erase("mesh");
        EXPECT_TRUE(lt::has(load_error(b),
                            "nodes[0].extensions.EXT_mesh_gpu_instancing: the "
                            "node places no mesh"));
    }
}

namespace {

/// Three scenes over three nodes, each placing the triangle at x = 0, 10 and 20: scene 0
/// node 0, scene 1 nodes 1 and 2 (the file's default), scene 2 nothing.
GltfBuilder three_scenes() {
    GltfBuilder b = lt::one_triangle();
    b.doc["nodes"] = {{{"mesh", 0}},
                      {{"mesh", 0}, {"translation", {10, 0, 0}}},
                      {{"mesh", 0}, {"translation", {20, 0, 0}}}};
    b.doc["scenes"] = {{{"nodes", {0}}}, {{"nodes", {1, 2}}}, {{"nodes", json::array()}}};
    b.doc["scene"] = 1;
    return b;
}

}  // namespace

TEST(GltfSceneChoice, EachSceneIndexLoadsItsOwnNodes) {
    ScratchDir dir;
    GltfLoadOptions o;
    GltfScene s = load(dir, three_scenes(), o);  // the file's default, scene 1
    ASSERT_EQ(s.instances.size(), 2u);
    EXPECT_EQ(s.instances[0].node, 1);
    EXPECT_EQ(s.instances[1].node, 2);
    o.scene = 0;
    s = load(dir, three_scenes(), o);
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].node, 0);
    o.scene = 2;
    EXPECT_TRUE(load(dir, three_scenes(), o).instances.empty());
    // Without "scene", the first.
    GltfBuilder no_default = three_scenes();
    no_default.doc.erase("scene");
    s = load(dir, no_default);
    ASSERT_EQ(s.instances.size(), 1u);
    EXPECT_EQ(s.instances[0].node, 0);
}

TEST(GltfSceneChoice, AnIndexOutOfRangeNamesTheValueAndTheCount) {
    GltfLoadOptions o;
    o.scene = 3;
    std::string e = load_error(three_scenes(), o);
    EXPECT_TRUE(lt::has(e, "file.gltf: scenes: scene 3 requested, the file has 3 (scenes 0 to 2)"))
        << e;
    o.scene = 9;
    e = load_error(lt::one_triangle(), o);
    EXPECT_TRUE(lt::has(e, "scene 9 requested, the file has 1 (scene 0)")) << e;
    GltfBuilder none = lt::one_triangle();
    none.doc.erase("scenes");
    none.doc.erase("scene");
    o.scene = 0;
    e = load_error(none, o);
    EXPECT_TRUE(lt::has(e, "scene 0 requested, the file has none")) << e;
    o.scene = -2;
    EXPECT_TRUE(lt::has(load_error(none, o), "GltfLoadOptions::scene = -2"));
}

TEST(GltfSceneChoice, SceneFileOptionsChoosesTheSceneAndAnObjHasOne) {
    ScratchDir dir;
    const fs::path p = dir.path() / "scenes.glb";
    lt::write_file(p, three_scenes().glb());
    SceneFileOptions o;
    EXPECT_EQ(load_scene_file(p, o).triangles_placed, 2u);
    o.scene = 0;
    const LoadedScene zero = load_scene_file(p, o);
    EXPECT_EQ(zero.triangles_placed, 1u);
    EXPECT_NEAR(zero.bounds.hi.x, 1.0f, 1e-6f);  // the triangle at the origin
    o.scene = 7;
    const std::string e = lt::error_of([&] { (void)load_scene_file(p, o); });
    EXPECT_TRUE(lt::has(e, "scene 7 requested, the file has 3 (scenes 0 to 2)")) << e;
    const fs::path obj = dir.path() / "tri.obj";
    lt::write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    o.scene = 0;
    EXPECT_EQ(load_scene_file(obj, o).triangles_placed, 1u);
    o.scene = 1;
    EXPECT_TRUE(lt::has(lt::error_of([&] { (void)load_scene_file(obj, o); }),
                        "scene 1 requested, an OBJ file has one (scene 0)"));
}

namespace {

/// Materials 0, 1, 2 and 3; variants 'Midnight', 'Beach', 'Street'. Primitive 0 (material
/// 0) maps Beach to material 1 and Midnight and Street to material 2; primitive 1
/// (material 3) has no mappings.
GltfBuilder with_variants() {
    GltfBuilder b = lt::one_triangle();
    const int pos = b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"];
    b.doc["materials"] = {
        {{"name", "own"}}, {{"name", "sand"}}, {{"name", "night"}}, {{"name", "other"}}};
    b.doc["extensionsUsed"] = {"KHR_materials_variants"};
    b.doc["extensions"]["KHR_materials_variants"]["variants"] = {
        {{"name", "Midnight"}}, {{"name", "Beach"}}, {{"name", "Street"}}};
    b.doc["meshes"][0]["primitives"] = {
        {{"attributes", {{"POSITION", pos}}},
         {"material", 0},
         {"extensions",
          {{"KHR_materials_variants",
            {{"mappings",
              {{{"material", 1}, {"variants", {1}}}, {{"material", 2}, {"variants", {0, 2}}}}}}}}}},
        {{"attributes", {{"POSITION", pos}}}, {"material", 3}}};
    return b;
}

/// The mappings of primitive 0.
json& mappings(GltfBuilder& b) {
    return b.doc["meshes"][0]["primitives"][0]["extensions"]["KHR_materials_variants"]["mappings"];
}

}  // namespace

TEST(GltfVariants, EachVariantGivesThePrimitiveItsMappedMaterial) {
    ScratchDir dir;
    GltfLoadOptions o;
    GltfScene s = load(dir, with_variants(), o);
    EXPECT_EQ(s.variants, (std::vector<std::string>{"Midnight", "Beach", "Street"}));
    ASSERT_EQ(s.meshes[0].primitives.size(), 2u);
    EXPECT_EQ(s.meshes[0].primitives[0].material, 0);  // no variant: its own
    EXPECT_EQ(s.meshes[0].primitives[1].material, 3);
    for (const auto& [name, material] :
         std::vector<std::pair<std::string, int>>{{"Midnight", 2}, {"Beach", 1}, {"Street", 2}}) {
        SCOPED_TRACE(name);
        o.variant = name;
        s = load(dir, with_variants(), o);
        EXPECT_EQ(s.meshes[0].primitives[0].material, material);
        EXPECT_EQ(s.meshes[0].primitives[1].material, 3);  // no mappings: unchanged
    }
    // A variant that a primitive's mappings do not name leaves its own material.
    GltfBuilder partial = with_variants();
    mappings(partial) = {{{"material", 1}, {"variants", {1}}}};
    o.variant = "Street";
    EXPECT_EQ(load(dir, partial, o).meshes[0].primitives[0].material, 0);
}

TEST(GltfVariants, AnUnknownNameListsTheKnownOnes) {
    GltfLoadOptions o;
    o.variant = "Nope";
    std::string e = load_error(with_variants(), o);
    EXPECT_TRUE(lt::has(e,
                        "file.gltf: extensions.KHR_materials_variants: variant 'Nope' is not "
                        "in the file (its variants: 'Midnight', 'Beach', 'Street')"))
        << e;
    e = load_error(lt::one_triangle(), o);
    EXPECT_TRUE(lt::has(e, "variant 'Nope' is not in the file (it defines no variants)")) << e;
    // Through load_scene_file, and an OBJ (no variants at all).
    ScratchDir dir;
    SceneFileOptions so;
    so.variant = "Nope";
    const fs::path p = dir.path() / "v.gltf";
    lt::write_file(p, with_variants().gltf());
    EXPECT_TRUE(lt::has(lt::error_of([&] { (void)load_scene_file(p, so); }), "'Street')"));
    const fs::path obj = dir.path() / "tri.obj";
    lt::write_file(obj, "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    EXPECT_TRUE(lt::has(lt::error_of([&] { (void)load_scene_file(obj, so); }),
                        "variant 'Nope': an OBJ file has no material variants"));
    so.variant = "Beach";
    EXPECT_EQ(load_scene_file(p, so).triangles_placed, 2u);
}

TEST(GltfVariants, BadMappingsAreErrorsNamingTheJsonPath) {
    const std::string where = "meshes[0].primitives[0].extensions.KHR_materials_variants.";
    GltfBuilder b = with_variants();
    mappings(b)[0]["material"] = 9;
    std::string e = load_error(b);
    EXPECT_TRUE(lt::has(e, where + "mappings[0].material: material 9 does not exist")) << e;
    b = with_variants();
    mappings(b)[1]["variants"] = {5};
    e = load_error(b);
    EXPECT_TRUE(lt::has(e, where + "mappings[1].variants[0]: variant 5 does not exist (3 in")) << e;
    b = with_variants();
    mappings(b)[1]["variants"] = {0, 1};
    e = load_error(b);
    EXPECT_TRUE(lt::has(e, where + "mappings[1].variants[1]: variant 1 is mapped already by "
                                   "mappings[0]"))
        << e;
    b = with_variants();
    mappings(b)[0].erase("material");
    EXPECT_TRUE(lt::has(load_error(b), where + "mappings[0].material: missing"));
    b = with_variants();
    mappings(b)[0]["material"] = 4294967297ull;
    EXPECT_TRUE(lt::has(load_error(b), where + "mappings[0].material: 4294967297 is too large"));
    b = with_variants();
    b.doc["extensions"]["KHR_materials_variants"]["variants"][1] = {{"label", "x"}};
    EXPECT_TRUE(lt::has(load_error(b),
                        "extensions.KHR_materials_variants.variants[1].name: "
                        "missing or not a string"));
}

TEST(GltfLightUnits, WattsDivideBy683PhotometricTakesTheNumbers) {
    GltfBuilder b = lt::one_triangle();
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    // A 3 lux sun, as GlamVelvetSofa's (a file authored for web viewers).
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"intensity", 1366.0}, {"color", {1.0, 0.5, 0.25}}},
        {{"type", "directional"}, {"intensity", 3.0}},
        {{"type", "spot"}, {"intensity", 683.0}, {"spot", {{"outerConeAngle", 0.5}}}}};
    for (int i = 0; i < 3; ++i)
        b.doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", i}}}}}});
    b.doc["scenes"] = {{{"nodes", {0, 1, 2, 3}}}};
    ScratchDir dir;
    const fs::path p = dir.path() / "lights.gltf";
    lt::write_file(p, b.gltf());
    SceneFileOptions o;
    EXPECT_EQ(o.light_units, PunctualLightUnits::Watts);  // the default, as before
    for (const PunctualLightUnits units :
         {PunctualLightUnits::Watts, PunctualLightUnits::Photometric}) {
        o.light_units = units;
        const float per = units == PunctualLightUnits::Watts ? 1.0f / 683.0f : 1.0f;
        const LoadedScene s = load_scene_file(p, o);
        ASSERT_EQ(s.scene.lights().size(), 3u);
        const auto* point = std::get_if<PointLight>(&s.scene.lights()[0].source);
        const auto* sun = std::get_if<DirectionalLight>(&s.scene.lights()[1].source);
        const auto* spot = std::get_if<SpotLight>(&s.scene.lights()[2].source);
        ASSERT_TRUE(point != nullptr && sun != nullptr && spot != nullptr);
        // Watts: 1366 cd -> 2 W/sr, 3 lux -> 0.0044 W/m^2, 683 cd -> 1 W/sr. Photometric:
        // 1366 W/sr, 3 W/m^2, 683 W/sr (times the colour).
        EXPECT_FLOAT_EQ(point->intensity.x, 1366.0f * per);
        EXPECT_FLOAT_EQ(point->intensity.y, 683.0f * per);
        EXPECT_FLOAT_EQ(sun->irradiance.x, 3.0f * per);
        EXPECT_FLOAT_EQ(spot->intensity.z, 683.0f * per);
    }
}
