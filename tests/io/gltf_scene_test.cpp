// scene_from_gltf / load_scene_file: the project's glTF scenes build a Scene with the counts
// their JSON states (computed here with nlohmann-json, not by the loader) and render to a
// finite, non-black image; nested transforms place a triangle where the composed transform
// says; a file's camera looks where its node points, with the predicted pixel for a known
// point; the one material mapping and the light units.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"
#include "test_support.h"

#include <librt/core/error.h>
#include <librt/gltf/gltf.h>
#include <librt/gltf/gltf_scene.h>
#include <librt/integrator/integrators.h>
#include <librt/loader/scene_file.h>
#include <librt/material/bsdf.h>
#include <librt/render/renderer.h>
#include <librt/sampling/warp.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <set>
#include <string>
#include <utility>

using namespace librt;
using librt::testing::GltfBuilder;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

json glb_json(const fs::path& p) {
    std::ifstream in(p, std::ios::binary);
    const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    std::uint32_t length = 0;
    std::memcpy(&length, bytes.data() + 12, 4);  // little-endian host (x86-64)
    return json::parse(bytes.substr(20, length));
}

struct Expected {
    std::size_t stored = 0, placed = 0, instances = 0, baked = 0, lights = 0;
    std::size_t stored_meshes = 0;  ///< a TriangleMesh per primitive: prototype or baked mesh
    bool emissive = false;
    /// glTF materials some primitive uses, and scene textures: one per (texture, colour
    /// space) those materials reference (base colour and emissive sRGB, the others linear).
    std::set<int> used_materials;
    std::set<std::pair<int, bool>> textures;
    std::size_t normal_mapped = 0, base_textured = 0, mr_textured = 0;  ///< used materials
    std::size_t prototypes_with_tangents = 0;  ///< primitives whose material has a normal map
};

/// From the JSON by the spec: n/3 triangles for mode 4 (n = indices' count, else
/// POSITION's), n - 2 for strips and fans; an instance per (node, primitive) of a mesh
/// placed by several nodes, a baked mesh per primitive of one placed once.
Expected expected_of(const json& doc) {
    Expected e;
    std::vector<std::size_t> tris, prims;
    for (const json& mesh : doc["meshes"]) {
        std::size_t t = 0;
        for (const json& prim : mesh["primitives"]) {
            const int mode = prim.value("mode", 4);
            const int acc = prim.contains("indices") ? prim["indices"].get<int>()
                                                     : prim["attributes"]["POSITION"].get<int>();
            const auto n = doc["accessors"][acc]["count"].get<std::size_t>();
            t += mode == 4 ? n / 3 : n - 2;
        }
        tris.push_back(t);
        prims.push_back(mesh["primitives"].size());
        e.stored += t;
        e.stored_meshes += mesh["primitives"].size();
    }
    for (const json& m : doc.value("materials", json::array())) {
        const json f = m.value("emissiveFactor", json::array({0, 0, 0}));
        if (f[0].get<float>() + f[1].get<float>() + f[2].get<float>() > 0.0f) e.emissive = true;
    }
    for (const json& mesh : doc["meshes"])
        for (const json& prim : mesh["primitives"])
            if (prim.contains("material")) {
                const int mi = prim["material"].get<int>();
                e.used_materials.insert(mi);
                if (doc["materials"][mi].contains("normalTexture")) ++e.prototypes_with_tangents;
            }
    for (const int mi : e.used_materials) {
        const json& m = doc["materials"][mi];
        const json pbr = m.value("pbrMetallicRoughness", json::object());
        const auto ref = [&](const json& owner, const char* key, bool srgb) {
            if (!owner.contains(key)) return false;
            e.textures.insert({owner[key]["index"].get<int>(), srgb});
            return true;
        };
        e.base_textured += ref(pbr, "baseColorTexture", true);
        e.mr_textured += ref(pbr, "metallicRoughnessTexture", false);
        ref(m, "emissiveTexture", true);
        e.normal_mapped += ref(m, "normalTexture", false);
    }
    std::vector<std::size_t> placements(tris.size(), 0);
    std::function<void(int)> visit = [&](int n) {
        const json& node = doc["nodes"][n];
        if (node.contains("mesh")) {
            const auto m = node["mesh"].get<std::size_t>();
            e.placed += tris[m];
            ++placements[m];
        }
        if (node.contains("extensions") && node["extensions"].contains("KHR_lights_punctual")) {
            e.lights += 1;  // point, spot and directional are all placed
        }
        for (const json& c : node.value("children", json::array())) visit(c.get<int>());
    };
    for (const json& r : doc["scenes"][doc.value("scene", 0)]["nodes"]) visit(r.get<int>());
    // A mesh placed by one node is baked into a world-space mesh; the others are a
    // prototype per primitive, placed by an instance per (node, primitive).
    for (std::size_t m = 0; m < tris.size(); ++m) {
        if (placements[m] == 1) {
            e.baked += prims[m];
        } else {
            e.instances += placements[m] * prims[m];
        }
    }
    return e;
}

void check_data_file(const fs::path& p) {
    const json doc = glb_json(p);
    const Expected want = expected_of(doc);
    SceneFileOptions options;
    options.width = options.height = 64;
    LoadedScene loaded = load_scene_file(p, options);
    EXPECT_EQ(loaded.triangles_stored, want.stored);
    EXPECT_EQ(loaded.triangles_placed, want.placed);
    EXPECT_EQ(loaded.scene.instance_count(), want.instances);
    // Stored once: one mesh per primitive (a prototype, or a baked mesh, which the top level
    // stores alike), however many nodes place it.
    EXPECT_EQ(loaded.scene.top_level().prototype_count(), want.stored_meshes);
    // Every object is an instance or a baked mesh (the loader adds no other geometry).
    EXPECT_EQ(loaded.scene.object_count(), want.instances + want.baked);
    // No punctual light, emissive surfaces or not: the studio lighting's sky and key light.
    const bool default_light = want.lights == 0;
    EXPECT_EQ(loaded.scene.lights().size(), want.lights + (default_light ? 2 : 0));
    EXPECT_EQ(loaded.lighting_note.empty(), !default_light);
    for (const std::string& w : loaded.warnings)
        EXPECT_EQ(w.find("not yet supported"), std::string::npos) << w;
    EXPECT_EQ(loaded.camera.width, 64);
    EXPECT_EQ(loaded.camera_name == "default", !doc.contains("cameras"));
    // Materials: every used glTF material is a MetallicRoughness one (after the default);
    // textures and normal maps as the JSON references them.
    const Scene& scene = loaded.scene;
    std::size_t kinds = 0, normal = 0, base = 0, mr = 0;
    for (std::size_t i = 0; i < scene.material_count(); ++i) {
        const Material& m = scene.material(std::uint32_t(i));
        kinds += m.kind == MaterialKind::MetallicRoughness;
        normal += m.normal_texture.bound();
        base += m.base_color_texture.bound();
        mr += m.metallic_roughness_texture.bound();
    }
    EXPECT_EQ(scene.material_count(), want.used_materials.size() + 1);  // + the default
    EXPECT_EQ(kinds, want.used_materials.size());
    EXPECT_EQ(scene.texture_count(), want.textures.size());
    EXPECT_EQ(normal, want.normal_mapped);
    EXPECT_EQ(base, want.base_textured);
    EXPECT_EQ(mr, want.mr_textured);
    std::size_t with_tangents = 0;
    for (std::size_t i = 0; i < scene.top_level().prototype_count(); ++i) {
        const TriangleMesh& mesh = scene.top_level().prototype_mesh(std::uint32_t(i));
        with_tangents += !mesh.tangents.empty();
        if (!mesh.tangents.empty()) {
            EXPECT_EQ(mesh.tangents.size(), mesh.positions.size());
        }
    }
    EXPECT_EQ(with_tangents, want.prototypes_with_tangents);

    loaded.scene.commit();
    PathTracerSettings pts;
    pts.max_depth = 3;
    PathTracer integrator(pts);
    RenderSettings settings;
    settings.samples_per_pixel = 4;
    settings.seed = 7;
    const Image image = render(loaded.scene, Camera(loaded.camera), integrator, settings);
    float brightest = 0.0f;
    for (const glm::vec3& px : image.pixels) {
        ASSERT_TRUE(std::isfinite(px.x) && std::isfinite(px.y) && std::isfinite(px.z));
        brightest = std::max({brightest, px.x, px.y, px.z});
    }
    EXPECT_GT(brightest, 0.0f) << p << " rendered black";
}

/// A big triangle in the plane x = -4 (covers y, z in [-100, 100] near the origin).
GltfBuilder wall_and_camera(double yfov, double aspect) {
    GltfBuilder b;
    const std::vector<float> p = {-4, -100, -100, -4, -100, 300, -4, 300, -100};
    const int pos = b.add_accessor(p, lt::kFloat, "VEC3", 3);
    b.doc["accessors"][pos]["min"] = {-4, -100, -100};
    b.doc["accessors"][pos]["max"] = {-4, 300, 300};
    b.doc["meshes"] = {{{"primitives", {{{"attributes", {{"POSITION", pos}}}}}}}};
    b.doc["cameras"] = {
        {{"type", "perspective"},
         {"name", "side"},
         {"perspective", {{"yfov", yfov}, {"aspectRatio", aspect}, {"znear", 0.1}}}}};
    const double h = std::sqrt(0.5);  // 90 degrees about +y: looking down -z turns to -x
    b.doc["nodes"] = {{{"mesh", 0}},
                      {{"camera", 0}, {"translation", {1, 2, 3}}, {"rotation", {0, h, 0, h}}}};
    b.doc["scenes"] = {{{"nodes", {0, 1}}}};
    b.doc["scene"] = 0;
    return b;
}

}  // namespace

TEST(GltfToSceneData, CornellPbr) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/cornell_pbr.glb");
    check_data_file(p);
}
TEST(GltfToSceneData, MaterialSpheres) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/material_spheres.glb");
    check_data_file(p);
}
TEST(GltfToSceneData, Textures) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/textures.glb");
    check_data_file(p);
}
TEST(GltfToSceneData, DragonsInstanced) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/dragons_instanced.glb");
    check_data_file(p);
}

TEST(GltfToScene, NestedTransformsPlaceTheTriangleWhereTheyComposeTo) {
    GltfBuilder b = lt::one_triangle();
    const double h = std::sqrt(0.5);  // 90 degrees about z: (0, 0, sin 45, cos 45)
    b.doc["nodes"] = json::array();
    b.doc["nodes"].push_back({{"translation", {1, 2, 3}},
                              {"rotation", {0, 0, h, h}},
                              {"scale", {2, 3, 4}},
                              {"children", {1}}});
    b.doc["nodes"].push_back(
        {{"matrix", {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1}}, {"children", {2}}});
    b.doc["nodes"].push_back({{"translation", {0, 0, 1}}, {"scale", {1, 1, 0.5}}, {"mesh", 0}});
    b.doc["scenes"] = {{{"nodes", {0}}}};
    ScratchDir dir;
    const fs::path p = dir.path() / "nested.gltf";
    lt::write_file(p, b.gltf());
    LoadedScene loaded = load_scene_file(p);
    loaded.scene.commit();
    // By hand, innermost first: z * 0.5 + 1; x + 5, y * 2; scale (2, 3, 4); 90 degrees
    // about z ((x, y) -> (-y, x)); + (1, 2, 3).
    auto predict = [](glm::vec3 v) {
        v = {v.x, v.y, v.z * 0.5f + 1.0f};
        v = {v.x + 5.0f, v.y * 2.0f, v.z};
        v = {v.x * 2.0f, v.y * 3.0f, v.z * 4.0f};
        v = {-v.y, v.x, v.z};
        return v + glm::vec3(1, 2, 3);
    };
    const glm::vec3 a = predict({0, 0, 0}), bb = predict({1, 0, 0}), c = predict({0, 1, 0});
    const glm::vec3 n = glm::normalize(glm::cross(bb - a, c - a));
    for (const glm::vec3 bary : {glm::vec3(1, 1, 1) / 3.0f, glm::vec3(0.6f, 0.2f, 0.2f)}) {
        const glm::vec3 target = bary.x * a + bary.y * bb + bary.z * c;
        const Ray ray(target + 3.0f * n, -n);
        Hit hit;
        ASSERT_TRUE(loaded.scene.intersect(ray, hit));
        EXPECT_NEAR(hit.t, 3.0f, 1e-4f);
        EXPECT_NEAR(glm::length(hit.point - target), 0.0f, 1e-4f);
    }
    // Off the triangle (beyond its hypotenuse) nothing is hit.
    const glm::vec3 outside = 0.1f * a + 0.6f * bb + 0.6f * c - 0.3f * a;
    Hit miss;
    EXPECT_FALSE(loaded.scene.intersect(Ray(outside + 3.0f * n, -n), miss));
}

TEST(GltfToScene, CameraLooksWhereItsNodePoints) {
    ScratchDir dir;
    const fs::path p = dir.path() / "camera.glb";
    lt::write_file(p, wall_and_camera(1.0, 2.0).glb());
    SceneFileOptions options;
    options.width = 101;  // odd sizes: pixel (50, 25) is exactly the image centre
    options.height = 51;
    LoadedScene loaded = load_scene_file(p, options);
    loaded.scene.commit();
    EXPECT_EQ(loaded.camera_name, "side");
    const Camera camera(loaded.camera);
    Sampler sampler(50, 25, 0, 1);
    const Ray ray = camera.generate_ray(50, 25, sampler);
    Hit hit;
    ASSERT_TRUE(loaded.scene.intersect(ray, hit));
    // Camera at (1, 2, 3) turned to look down -x: the centre ray meets x = -4 at (-4, 2, 3).
    EXPECT_NEAR(hit.point.x, -4.0f, 1e-4f);
    EXPECT_NEAR(hit.point.y, 2.0f, 1e-4f);
    EXPECT_NEAR(hit.point.z, 3.0f, 1e-4f);
    // znear 0.1 is the camera's near clip; no zfar: no far clip.
    EXPECT_FLOAT_EQ(loaded.camera.near_clip, 0.1f);
    EXPECT_TRUE(std::isinf(loaded.camera.far_clip));
    EXPECT_FLOAT_EQ(ray.t_min, 0.1f);  // the centre ray runs along the view axis
}

TEST(GltfToScene, AspectAndYfovGiveThePredictedPixel) {
    ScratchDir dir;
    const fs::path p = dir.path() / "camera.glb";
    const double yfov = 60.0 * kPi / 180.0;
    lt::write_file(p, wall_and_camera(yfov, 2.0).glb());
    SceneFileOptions options;
    options.default_long_side = 200;  // the size follows aspectRatio 2: 200 x 100
    LoadedScene loaded = load_scene_file(p, options);
    loaded.scene.commit();
    ASSERT_EQ(loaded.camera.width, 200);
    ASSERT_EQ(loaded.camera.height, 100);
    // Q is 5 ahead, 2 to the right (camera right = world -z) and 1 up. A pinhole of
    // vertical fov yfov over H rows has focal length f = H / (2 tan(yfov / 2)) pixels;
    // Q projects to column W/2 - 0.5 + f dx / 5, row H/2 - 0.5 - f dy / 5.
    const glm::vec3 q(-4.0f, 3.0f, 1.0f);
    const double f = 100.0 / (2.0 * std::tan(yfov / 2.0));
    const double col = 99.5 + f * 2.0 / 5.0, row = 49.5 - f * 1.0 / 5.0;
    const int px = int(std::lround(col)), py = int(std::lround(row));
    const Camera camera(loaded.camera);
    Sampler sampler(px, py, 0, 1);
    Hit hit;
    ASSERT_TRUE(loaded.scene.intersect(camera.generate_ray(px, py, sampler), hit));
    // The pixel centre's ray lands within the rounding distance (in pixels, times the
    // pixel's footprint 5 / f at the wall) of Q.
    const double footprint = 5.0 / f;
    EXPECT_NEAR(hit.point.z, q.z, (std::abs(col - px) + 1e-3) * footprint);
    EXPECT_NEAR(hit.point.y, q.y, (std::abs(row - py) + 1e-3) * footprint);
}

TEST(GltfToScene, UnknownCameraIsAnErrorListingTheCameras) {
    ScratchDir dir;
    const fs::path p = dir.path() / "camera.glb";
    lt::write_file(p, wall_and_camera(1.0, 1.0).glb());
    SceneFileOptions options;
    options.camera = "front";
    try {
        (void)load_scene_file(p, options);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("camera = front"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("'side'"), std::string::npos) << e.what();
    }
    options.camera = "0";
    EXPECT_EQ(load_scene_file(p, options).camera_name, "side");
}

TEST(GltfToScene, MaterialMapping) {
    // Every glTF material is the metallic-roughness kind, its factors as stated.
    GltfMaterial m;
    m.base_color_factor = {0.5f, 0.25f, 1.0f, 0.75f};
    m.metallic_factor = 0.0f;
    m.roughness_factor = 0.4f;
    m.emissive_factor = {1.0f, 0.5f, 0.0f};
    m.emissive_strength = 15.0f;
    GltfMaterialTextures ids;
    ids.base_color = 3;
    ids.normal = 5;
    m.base_color_texture.texture = 0;
    m.normal_texture.texture = 1;
    m.normal_texture.scale = 0.5f;
    Material d = material_from_gltf(m, ids);
    EXPECT_EQ(d.kind, MaterialKind::MetallicRoughness);
    EXPECT_EQ(d.base_color, glm::vec3(0.5f, 0.25f, 1.0f));
    EXPECT_EQ(d.albedo, glm::vec3(1.0f));
    EXPECT_FLOAT_EQ(d.roughness, 0.4f);
    EXPECT_FLOAT_EQ(d.metallic, 0.0f);
    EXPECT_FLOAT_EQ(d.ior, 1.5f);
    EXPECT_FLOAT_EQ(d.emission.x, 15.0f);
    EXPECT_FLOAT_EQ(d.emission.y, 7.5f);
    EXPECT_EQ(d.base_color_texture.texture, 3);
    EXPECT_EQ(d.normal_texture.texture, 5);
    EXPECT_FALSE(d.metallic_roughness_texture.bound());
    EXPECT_FLOAT_EQ(d.normal_scale, 0.5f);
    EXPECT_FLOAT_EQ(d.alpha, 0.75f);
    EXPECT_EQ(d.alpha_cutoff, 0.0f);  // OPAQUE: no alpha test
    EXPECT_FALSE(d.double_sided);     // glTF's default
    // The slot maps glTF uvs (v down) to ImageTexture's (v up).
    EXPECT_EQ(d.base_color_texture.map({0.25f, 0.25f}), glm::vec2(0.25f, 0.75f));
    // Transmission and KHR_materials_ior: thin transmission, double-sided.
    m.transmission_factor = 1.0f;
    m.ior = 1.33f;
    d = material_from_gltf(m);
    EXPECT_EQ(d.kind, MaterialKind::MetallicRoughness);
    EXPECT_FLOAT_EQ(d.transmission, 1.0f);
    EXPECT_FLOAT_EQ(d.ior, 1.33f);
    EXPECT_TRUE(d.double_sided);
    // MASK with its cut-off; BLEND as partial coverage (no cut-off).
    m.transmission_factor = 0.0f;
    m.alpha_mode = GltfAlphaMode::Mask;
    m.alpha_cutoff = 0.3f;
    EXPECT_FLOAT_EQ(material_from_gltf(m).alpha_cutoff, 0.3f);
    EXPECT_FALSE(material_from_gltf(m).alpha_blend);
    m.alpha_mode = GltfAlphaMode::Blend;
    EXPECT_TRUE(material_from_gltf(m).alpha_blend);
    EXPECT_EQ(material_from_gltf(m).alpha_cutoff, 0.0f);
    EXPECT_TRUE(material_from_gltf(m).cuts_out());
    m.double_sided = true;
    EXPECT_TRUE(material_from_gltf(m).double_sided);
}

TEST(GltfToScene, AlphaModesAndDoubleSidedFromTheFile) {
    // One triangle in z = 0 facing +z (counter-clockwise seen from +z), its material's
    // alpha as the file states; a ray from +z through its middle.
    const auto load = [](const json& material) {
        GltfBuilder b = lt::one_triangle();
        b.doc["materials"] = {material};
        b.doc["meshes"][0]["primitives"][0]["material"] = 0;
        ScratchDir dir;
        const fs::path p = dir.path() / "alpha.gltf";
        lt::write_file(p, b.gltf());
        LoadedScene loaded = load_scene_file(p);
        loaded.scene.commit();
        return loaded;
    };
    const Ray down({0.25f, 0.25f, 1.0f}, {0, 0, -1}), up({0.25f, 0.25f, -1.0f}, {0, 0, 1});
    Hit hit;
    json m = {{"alphaMode", "MASK"},
              {"alphaCutoff", 0.5},
              {"pbrMetallicRoughness", {{"baseColorFactor", {1, 1, 1, 0.3}}}}};
    EXPECT_FALSE(load(m).scene.intersect(down, hit));  // 0.3 < 0.5: cut out
    m["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 0.7};
    EXPECT_TRUE(load(m).scene.intersect(down, hit));
    m["alphaMode"] = "OPAQUE";
    m["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 0.0};
    EXPECT_TRUE(load(m).scene.intersect(down, hit));  // alpha ignored
    // BLEND: partial coverage, no warning (tests/render/surface_rules_test.cpp renders it).
    m["alphaMode"] = "BLEND";
    m["pbrMetallicRoughness"]["baseColorFactor"] = {1, 1, 1, 0.4};
    const LoadedScene blend = load(m);
    std::size_t blend_materials = 0;
    for (std::size_t i = 0; i < blend.scene.material_count(); ++i)
        blend_materials += blend.scene.material(std::uint32_t(i)).alpha_blend;
    EXPECT_EQ(blend_materials, 1u);
    for (const std::string& w : blend.warnings) EXPECT_EQ(w.find("BLEND"), std::string::npos) << w;
    // doubleSided false (glTF's default): camera rays pass the back (culled), other rays find
    // it black; true: both sides as stated.
    const json one_sided = {{"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1}}}}};
    LoadedScene s = load(one_sided);
    ShadedMaterial scratch;
    ASSERT_TRUE(s.scene.intersect(up, hit));
    EXPECT_TRUE(s.scene.camera_passes(hit, up.direction));
    EXPECT_EQ(lobes(s.scene.shade(hit, up.direction, scratch)), BsdfLobe::None);
    ASSERT_TRUE(s.scene.intersect(down, hit));
    EXPECT_FALSE(s.scene.camera_passes(hit, down.direction));
    EXPECT_EQ(s.scene.shade(hit, down.direction, scratch).kind, MaterialKind::MetallicRoughness);
    json two_sided = one_sided;
    two_sided["doubleSided"] = true;
    s = load(two_sided);
    ASSERT_TRUE(s.scene.intersect(up, hit));
    EXPECT_FALSE(s.scene.camera_passes(hit, up.direction));
    EXPECT_EQ(s.scene.shade(hit, up.direction, scratch).kind, MaterialKind::MetallicRoughness);
}

TEST(GltfToScene, PunctualLightsBecomeRadiometricBy683) {
    GltfBuilder b = lt::one_triangle();
    b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] = {
        {{"type", "point"}, {"intensity", 1366.0}, {"color", {1.0, 0.5, 0.25}}},
        {{"type", "directional"}, {"intensity", 100.0}},
        {{"type", "spot"},
         {"intensity", 683.0},
         {"spot", {{"innerConeAngle", 0.1}, {"outerConeAngle", 0.5}}}}};
    b.doc["nodes"].push_back(
        {{"translation", {0, 0, 2}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
    b.doc["nodes"].push_back({{"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
    // A spot at (1, 0, 0) turned by 90 degrees about y: local -z becomes world -x.
    b.doc["nodes"].push_back({{"translation", {1, 0, 0}},
                              {"rotation", {0.0, 0.70710678, 0.0, 0.70710678}},
                              {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
    b.doc["scenes"] = {{{"nodes", {0, 1, 2, 3}}}};
    ScratchDir dir;
    const fs::path p = dir.path() / "lights.gltf";
    lt::write_file(p, b.gltf());
    const LoadedScene loaded = load_scene_file(p);
    ASSERT_EQ(loaded.scene.lights().size(), 3u);
    const auto* point = std::get_if<PointLight>(&loaded.scene.lights()[0].source);
    ASSERT_NE(point, nullptr);
    // 1366 cd / 683 lm/W = 2 W/sr, times the colour.
    EXPECT_FLOAT_EQ(point->intensity.x, 2.0f);
    EXPECT_FLOAT_EQ(point->intensity.z, 0.5f);
    EXPECT_FLOAT_EQ(point->position.z, 2.0f);
    // 100 lux / 683 lm/W of irradiance, from +z (the sun shines down its node's -z).
    const auto* sun = std::get_if<DirectionalLight>(&loaded.scene.lights()[1].source);
    ASSERT_NE(sun, nullptr);
    EXPECT_FLOAT_EQ(sun->irradiance.y, 100.0f / 683.0f);
    EXPECT_NEAR(glm::normalize(sun->to_light).z, 1.0f, 1e-6f);
    // 683 cd -> 1 W/sr on the axis, the cone angles kept, the axis along world -x.
    const auto* spot = std::get_if<SpotLight>(&loaded.scene.lights()[2].source);
    ASSERT_NE(spot, nullptr);
    EXPECT_FLOAT_EQ(spot->intensity.x, 1.0f);
    EXPECT_FLOAT_EQ(spot->inner_angle, 0.1f);
    EXPECT_FLOAT_EQ(spot->outer_angle, 0.5f);
    EXPECT_NEAR(spot->position.x, 1.0f, 1e-6f);
    EXPECT_NEAR(glm::normalize(spot->direction).x, -1.0f, 1e-6f);
    for (const std::string& w : loaded.warnings)
        EXPECT_EQ(w.find("not yet supported"), std::string::npos) << w;
}

TEST(SceneFile, UnknownExtensionIsAnError) {
    EXPECT_THROW((void)load_scene_file("scene.fbx"), Error);
}

TEST(SceneFile, ObjBecomesASceneFramedAndLit) {
    ScratchDir dir;
    const fs::path p = dir.path() / "quad.obj";
    lt::write_file(p, "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nf 1 2 3 4\n");
    LoadedScene loaded = load_scene_file(p);
    EXPECT_EQ(loaded.triangles_stored, 2u);
    EXPECT_EQ(loaded.scene.lights().size(), 2u);  // the studio lighting's sky and key light
    EXPECT_FALSE(loaded.lighting_note.empty());
    EXPECT_EQ(loaded.camera_name, "default");
    loaded.scene.commit();
    // The default camera centres the quad's projection (frame_bounds): seen from straight in
    // front (x = 0) and 15 degrees above, the image centre sees the quad on its vertical
    // centre line, near its centre (perspective moves the projection's centre off the
    // quad's by a little: 0.09 here, of a half size of 1).
    CameraSettings s = loaded.camera;
    s.width = s.height = 11;
    const Camera camera(s);
    Sampler sampler(5, 5, 0, 1);
    Hit hit;
    ASSERT_TRUE(loaded.scene.intersect(camera.generate_ray(5, 5, sampler), hit));
    EXPECT_NEAR(hit.point.x, 0.0f, 1e-4f);
    EXPECT_LT(std::abs(hit.point.y), 0.15f);
}

// A mesh placed by one node is baked into world space; placed by two, it stays a prototype
// with an instance per node. Both must put the same surface in the same place: hit points,
// both normals and uvs, under a rotation, a non-uniform scale and a mirror (scale y < 0).
TEST(GltfToScene, ABakedMeshMatchesTheSameMeshInstanced) {
    GltfBuilder b = lt::one_triangle();
    const std::vector<float> normals = {0, 0, 1, 0.6f, 0, 0.8f, 0, 0.6f, 0.8f};
    const std::vector<float> uvs = {0, 0, 1, 0, 0, 1};
    b.doc["meshes"][0]["primitives"][0]["attributes"]["NORMAL"] =
        b.add_accessor(normals, lt::kFloat, "VEC3", 3);
    b.doc["meshes"][0]["primitives"][0]["attributes"]["TEXCOORD_0"] =
        b.add_accessor(uvs, lt::kFloat, "VEC2", 3);
    // Textured, so that the mesh keeps its uvs (without, a hit's uv is its barycentrics).
    b.doc["images"] = {{{"uri", "data:image/png;base64," + lt::base64(lt::tiny_png())}}};
    b.doc["textures"] = {{{"source", 0}}};
    b.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}};
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    const json placed = {{"mesh", 0},
                         {"translation", {0.3, -0.2, 0.5}},
                         {"rotation", {0.2, 0.3, 0.1, 0.9273618495495703}},
                         {"scale", {2.0, -1.0, 1.5}}};
    ScratchDir dir;
    b.doc["nodes"] = {placed};
    lt::write_file(dir.path() / "once.gltf", b.gltf());
    b.doc["nodes"] = {placed, {{"mesh", 0}, {"translation", {100, 0, 0}}}};
    b.doc["scenes"] = {{{"nodes", {0, 1}}}};
    lt::write_file(dir.path() / "twice.gltf", b.gltf());
    LoadedScene once = load_scene_file(dir.path() / "once.gltf");
    LoadedScene twice = load_scene_file(dir.path() / "twice.gltf");
    EXPECT_EQ(once.scene.instance_count(), 0u);
    EXPECT_EQ(once.scene.object_count(), 1u);
    EXPECT_EQ(twice.scene.instance_count(), 2u);
    once.scene.commit();
    twice.scene.commit();
    // A fan of rays from one point toward the triangle's world box (in the once scene,
    // whose bounds are the triangle's alone).
    const glm::vec3 lo = once.bounds.lo, hi = once.bounds.hi;
    const glm::vec3 eye = 0.5f * (lo + hi) + glm::vec3(1.0f, 2.0f, 6.0f);
    int hits = 0;
    for (int i = 0; i <= 20; ++i) {
        for (int j = 0; j <= 20; ++j) {
            const glm::vec3 target =
                lo + (hi - lo) * glm::vec3(float(i) / 20.0f, float(j) / 20.0f, 0.5f);
            const Ray ray(eye, target - eye);
            Hit a, c;
            const bool hit_once = once.scene.intersect(ray, a);
            ASSERT_EQ(hit_once, twice.scene.intersect(ray, c)) << i << "," << j;
            if (!hit_once) continue;
            ++hits;
            for (int k = 0; k < 3; ++k) {
                EXPECT_NEAR(a.point[k], c.point[k], 1e-5f) << i << "," << j;
                EXPECT_NEAR(a.geometric_normal[k], c.geometric_normal[k], 1e-5f) << i << "," << j;
                EXPECT_NEAR(a.shading_normal[k], c.shading_normal[k], 1e-5f) << i << "," << j;
            }
            EXPECT_NEAR(a.uv.x, c.uv.x, 1e-5f);
            EXPECT_NEAR(a.uv.y, c.uv.y, 1e-5f);
            EXPECT_EQ(a.instance_id, kInvalidId);
            EXPECT_NE(c.instance_id, kInvalidId);
        }
    }
    EXPECT_GT(hits, 50);  // the fan covers the triangle, not only its box's empty half
}

TEST(GltfToScene, ANodeScaledToZeroIsWarnedAboutNotPlaced) {
    GltfBuilder b = lt::one_triangle();
    b.doc["nodes"] = {{{"mesh", 0}}, {{"mesh", 0}, {"scale", {0, 0, 0}}, {"name", "hidden"}}};
    b.doc["scenes"] = {{{"nodes", {0, 1}}}};
    ScratchDir dir;
    const fs::path p = dir.path() / "hidden.gltf";
    lt::write_file(p, b.gltf());
    const LoadedScene loaded = load_scene_file(p);
    // The visible node places the mesh, once: baked into a world-space mesh.
    EXPECT_EQ(loaded.scene.object_count(), 1u);
    EXPECT_EQ(loaded.scene.instance_count(), 0u);
    EXPECT_EQ(loaded.triangles_placed, 1u);
    bool warned = false;
    for (const std::string& w : loaded.warnings)
        warned = warned ||
                 w.find("nodes[1] 'hidden': its world transform is singular") != std::string::npos;
    EXPECT_TRUE(warned);
}
