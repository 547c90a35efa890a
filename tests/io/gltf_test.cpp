// load_gltf on the project's glTF scenes (counts computed here from their JSON with
// nlohmann-json, not by the loader) and on small files written by the tests: transforms
// composed by hand, every primitive mode, index and attribute encoding, sparse accessors,
// cameras, lights, materials and textures.

#include "io/gltf_test_util.h"
#include "robustness/robustness_util.h"
#include "test_support.h"

#include <librt/gltf/gltf.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::glb_json;
using librt::testing::GltfBuilder;
using librt::testing::ScratchDir;
using nlohmann::json;
namespace fs = std::filesystem;
namespace lt = librt::testing;

namespace {

struct Counts {
    std::size_t meshes = 0, triangles_stored = 0, triangles_placed = 0, instances = 0,
                materials = 0, textures = 0, cameras = 0, lights = 0;
    std::vector<std::size_t> mesh_triangles;
};

/// Expected counts from the glTF JSON, by the spec: a primitive of n vertices (indices'
/// count, else POSITION's) has n/3 triangles (mode 4, the default) or n-2 (strip, fan).
Counts expected_counts(const json& doc) {
    Counts c;
    c.meshes = doc["meshes"].size();
    for (const json& mesh : doc["meshes"]) {
        std::size_t t = 0;
        for (const json& prim : mesh["primitives"]) {
            const int mode = prim.value("mode", 4);
            const std::size_t n =
                prim.contains("indices")
                    ? doc["accessors"][prim["indices"].get<int>()]["count"].get<std::size_t>()
                    : doc["accessors"][prim["attributes"]["POSITION"].get<int>()]["count"]
                          .get<std::size_t>();
            if (mode == 4) t += n / 3;
            if (mode == 5 || mode == 6) t += n - 2;
        }
        c.mesh_triangles.push_back(t);
        c.triangles_stored += t;
    }
    c.materials = doc.contains("materials") ? doc["materials"].size() : 0;
    c.textures = doc.contains("textures") ? doc["textures"].size() : 0;
    std::function<void(int)> visit = [&](int n) {
        const json& node = doc["nodes"][n];
        if (node.contains("mesh")) {
            ++c.instances;
            c.triangles_placed += c.mesh_triangles[node["mesh"].get<std::size_t>()];
        }
        if (node.contains("camera")) ++c.cameras;
        if (node.contains("extensions") && node["extensions"].contains("KHR_lights_punctual"))
            ++c.lights;
        if (node.contains("children"))
            for (const json& ch : node["children"]) visit(ch.get<int>());
    };
    for (const json& root : doc["scenes"][doc.value("scene", 0)]["nodes"]) visit(root.get<int>());
    return c;
}

/// Rotation matrix of the unit quaternion (x, y, z, w) (the standard formula, e.g.
/// Shoemake 1985), written out rather than taken from glm.
glm::mat4 quat_matrix(double x, double y, double z, double w) {
    glm::mat4 m(1.0f);
    // glm::mat4 is [column][row].
    m[0][0] = float(1 - 2 * (y * y + z * z));
    m[1][0] = float(2 * (x * y - z * w));
    m[2][0] = float(2 * (x * z + y * w));
    m[0][1] = float(2 * (x * y + z * w));
    m[1][1] = float(1 - 2 * (x * x + z * z));
    m[2][1] = float(2 * (y * z - x * w));
    m[0][2] = float(2 * (x * z - y * w));
    m[1][2] = float(2 * (y * z + x * w));
    m[2][2] = float(1 - 2 * (x * x + y * y));
    return m;
}

/// T * R * S of a node's JSON, by hand.
glm::mat4 node_matrix(const json& node) {
    if (node.contains("matrix")) {
        glm::mat4 m;
        for (int i = 0; i < 16; ++i) m[i / 4][i % 4] = node["matrix"][i].get<float>();
        return m;
    }
    glm::mat4 t(1.0f), r(1.0f), s(1.0f);
    if (node.contains("translation"))
        for (int i = 0; i < 3; ++i) t[3][i] = node["translation"][i].get<float>();
    if (node.contains("rotation")) {
        const json& q = node["rotation"];
        r = quat_matrix(q[0], q[1], q[2], q[3]);
    }
    if (node.contains("scale"))
        for (int i = 0; i < 3; ++i) s[i][i] = node["scale"][i].get<float>();
    return t * r * s;
}

void expect_near(const glm::mat4& a, const glm::mat4& b, float tol) {
    for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
            EXPECT_NEAR(a[c][r], b[c][r], tol) << "[" << c << "][" << r << "]";
}

void check_data_file(const fs::path& p) {
    const json doc = glb_json(p);
    const Counts want = expected_counts(doc);
    const GltfScene scene = load_gltf(p);
    EXPECT_TRUE(scene.warnings.empty()) << scene.warnings.front();
    EXPECT_EQ(scene.meshes.size(), want.meshes);
    EXPECT_EQ(scene.triangles_stored(), want.triangles_stored);
    EXPECT_EQ(scene.triangles_placed(), want.triangles_placed);
    EXPECT_EQ(scene.instances.size(), want.instances);
    EXPECT_EQ(scene.materials.size(), want.materials);
    EXPECT_EQ(scene.textures.size(), want.textures);
    EXPECT_EQ(scene.cameras.size(), want.cameras);
    EXPECT_EQ(scene.lights.size(), want.lights);
    // Every instance at its node's transform (the data files' nodes are all roots).
    for (const GltfInstance& inst : scene.instances)
        expect_near(inst.world, node_matrix(doc["nodes"][inst.node]), 1e-5f);
    // Materials as the JSON states them.
    for (std::size_t i = 0; i < scene.materials.size(); ++i) {
        const json& m = doc["materials"][i];
        const json pbr = m.value("pbrMetallicRoughness", json::object());
        EXPECT_FLOAT_EQ(scene.materials[i].metallic_factor, pbr.value("metallicFactor", 1.0f));
        EXPECT_FLOAT_EQ(scene.materials[i].roughness_factor, pbr.value("roughnessFactor", 1.0f));
        if (pbr.contains("baseColorFactor")) {
            EXPECT_FLOAT_EQ(scene.materials[i].base_color_factor.y,
                            pbr["baseColorFactor"][1].get<float>());
        }
        EXPECT_EQ(scene.materials[i].double_sided, m.value("doubleSided", false));
    }
    // Every texture's image decoded.
    for (const GltfTexture& t : scene.textures) {
        ASSERT_GE(t.image, 0);
        const GltfImage& img = scene.images[std::size_t(t.image)];
        EXPECT_GT(img.width, 0);
        EXPECT_EQ(img.rgba.size(), std::size_t(img.width) * std::size_t(img.height) * 4);
    }
    // Every primitive's arrays agree, and its indices are in range.
    for (const GltfMesh& m : scene.meshes)
        for (const GltfPrimitive& prim : m.primitives) {
            for (const std::size_t n : {prim.normals.size(), prim.tangents.size(), prim.uv0.size()})
                EXPECT_TRUE(n == 0 || n == prim.positions.size());
            for (const glm::uvec3& t : prim.triangles)
                ASSERT_LT(std::max({t.x, t.y, t.z}), prim.positions.size());
        }
}

}  // namespace

TEST(GltfData, CornellPbr) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/cornell_pbr.glb");
    check_data_file(p);
    const GltfScene scene = load_gltf(p);
    // The data README: 9 meshes, 7,960 triangles, an emissive panel of strength 15, a
    // glass cube (transmission, IOR 1.5), a 40 degree camera.
    EXPECT_EQ(scene.triangles_stored(), 7960u);
    bool panel = false, glass = false;
    for (const GltfMaterial& m : scene.materials) {
        panel |= m.emissive_strength == 15.0f;
        glass |= m.transmission_factor > 0.0f;
    }
    EXPECT_TRUE(panel);
    EXPECT_TRUE(glass);
    ASSERT_EQ(scene.cameras.size(), 1u);
    EXPECT_NEAR(scene.cameras[0].yfov, 40.0 * 3.14159265358979 / 180.0, 1e-6);
}

TEST(GltfData, MaterialSpheres) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/material_spheres.glb");
    check_data_file(p);
    const GltfScene scene = load_gltf(p);
    ASSERT_EQ(scene.lights.size(), 2u);
    // The data README: a sun of 2,049 lux and a point light of 10,870 cd.
    int suns = 0, points = 0;
    for (const GltfLight& l : scene.lights) {
        if (l.type == GltfLight::Type::Directional) {
            ++suns;
            EXPECT_FLOAT_EQ(l.intensity, 2049.0f);
        } else if (l.type == GltfLight::Type::Point) {
            ++points;
            EXPECT_NEAR(l.intensity, 10870.28f, 0.01f);
        }
    }
    EXPECT_EQ(suns, 1);
    EXPECT_EQ(points, 1);
}

TEST(GltfData, Textures) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/textures.glb");
    check_data_file(p);
    const GltfScene scene = load_gltf(p);
    EXPECT_EQ(scene.textures.size(), 3u);
    for (const GltfMesh& m : scene.meshes)
        for (const GltfPrimitive& prim : m.primitives) {
            EXPECT_FALSE(prim.tangents.empty());  // exported with tangents
            EXPECT_FALSE(prim.uv0.empty());
        }
}

TEST(GltfData, DragonsInstanced) {
    LIBRT_REQUIRE_DATA_FILE(p, "gltf/dragons_instanced.glb");
    check_data_file(p);
    const GltfScene scene = load_gltf(p);
    // The data README: the dragon (871,414 triangles) stored once, placed by 64 nodes.
    std::size_t dragons = 0;
    for (const GltfInstance& i : scene.instances)
        dragons += scene.meshes[std::size_t(i.mesh)].triangle_count() == 871414u;
    EXPECT_EQ(dragons, 64u);
    EXPECT_GT(scene.triangles_placed(), 55'700'000u);
}

// Nested nodes: root (translation, rotation, non-uniform scale) -> matrix node -> TRS node
// with the mesh. The world matrix and the placed vertices are predicted by hand.
TEST(GltfTransforms, NestedNodesPlaceTheTriangleWherePredicted) {
    GltfBuilder b = lt::one_triangle();
    const double h = std::sqrt(0.5);  // 90 degrees about z: (0, 0, sin 45, cos 45)
    b.doc["nodes"] = json::array();
    b.doc["nodes"].push_back({{"translation", {1, 2, 3}},
                              {"rotation", {0, 0, h, h}},
                              {"scale", {2, 3, 4}},
                              {"children", {1}}});
    // Column-major: x' = x + 5 (translation in the last column) and y doubled.
    b.doc["nodes"].push_back(
        {{"matrix", {1, 0, 0, 0, 0, 2, 0, 0, 0, 0, 1, 0, 5, 0, 0, 1}}, {"children", {2}}});
    b.doc["nodes"].push_back({{"translation", {0, 0, 1}}, {"scale", {1, 1, 0.5}}, {"mesh", 0}});
    b.doc["scenes"] = {{{"nodes", {0}}}};
    ScratchDir dir;
    const fs::path p = dir.path() / "nested.gltf";
    lt::write_file(p, b.gltf());
    const GltfScene scene = load_gltf(p);
    ASSERT_EQ(scene.instances.size(), 1u);
    const glm::mat4 want = node_matrix(b.doc["nodes"][0]) * node_matrix(b.doc["nodes"][1]) *
                           node_matrix(b.doc["nodes"][2]);
    expect_near(scene.instances[0].world, want, 1e-5f);
    // By hand: v -> node2 (z*0.5 + 1) -> node1 (x + 5, y * 2) -> scale (2, 3, 4) -> rotate
    // 90 deg about z ((x, y) -> (-y, x)) -> + (1, 2, 3).
    auto predict = [](glm::vec3 v) {
        v = {v.x, v.y, v.z * 0.5f + 1.0f};
        v = {v.x + 5.0f, v.y * 2.0f, v.z};
        v = {v.x * 2.0f, v.y * 3.0f, v.z * 4.0f};
        v = {-v.y, v.x, v.z};
        return v + glm::vec3(1, 2, 3);
    };
    const GltfPrimitive& prim = scene.meshes[0].primitives[0];
    for (const glm::vec3& v : prim.positions) {
        const glm::vec3 placed = glm::vec3(scene.instances[0].world * glm::vec4(v, 1.0f));
        const glm::vec3 expected = predict(v);
        EXPECT_NEAR(placed.x, expected.x, 1e-4f);
        EXPECT_NEAR(placed.y, expected.y, 1e-4f);
        EXPECT_NEAR(placed.z, expected.z, 1e-4f);
    }
    // Vertex (1, 0, 0): (6, 0, 1) -> (12, 0, 4) -> (0, 12, 4) -> (1, 14, 7).
    const glm::vec3 p1 = glm::vec3(scene.instances[0].world * glm::vec4(1, 0, 0, 1));
    EXPECT_NEAR(p1.x, 1.0f, 1e-4f);
    EXPECT_NEAR(p1.y, 14.0f, 1e-4f);
    EXPECT_NEAR(p1.z, 7.0f, 1e-4f);
}

TEST(GltfTransforms, AMeshUsedByManyNodesIsStoredOnce) {
    GltfBuilder b = lt::one_triangle();
    b.doc["nodes"] = json::array();
    for (int i = 0; i < 64; ++i)
        b.doc["nodes"].push_back({{"mesh", 0}, {"translation", {i, 0, 0}}});
    json roots = json::array();
    for (int i = 0; i < 64; ++i) roots.push_back(i);
    b.doc["scenes"] = {{{"nodes", roots}}};
    ScratchDir dir;
    const fs::path p = dir.path() / "many.glb";
    lt::write_file(p, b.glb());
    const GltfScene scene = load_gltf(p);
    EXPECT_EQ(scene.meshes.size(), 1u);
    EXPECT_EQ(scene.triangles_stored(), 1u);
    EXPECT_EQ(scene.triangles_placed(), 64u);
    for (const GltfInstance& i : scene.instances) EXPECT_FLOAT_EQ(i.world[3][0], float(i.node));
}
