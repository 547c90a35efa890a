#include "test_support.h"

#include <librt/core/error.h>
#include <librt/obj/obj.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace librt;
namespace fs = std::filesystem;

namespace {

/// A fresh directory under the system temp dir, removed with everything in it.
class TempDir {
public:
    TempDir() {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = fs::temp_directory_path() / ("librt_obj_" + std::string(info ? info->name() : "x") +
                                             "_" + std::to_string(counter++));
        fs::remove_all(path_);
        fs::create_directories(path_);
    }
    ~TempDir() {
        std::error_code ignored;
        fs::remove_all(path_, ignored);
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;

    /// Writes text to name inside the directory and returns its path.
    fs::path write(const std::string& name, const std::string& text) const {
        const fs::path p = path_ / name;
        fs::create_directories(p.parent_path());
        std::ofstream(p, std::ios::binary) << text;
        return p;
    }
    [[nodiscard]] const fs::path& path() const { return path_; }

private:
    fs::path path_;
};

/// load_obj collecting warnings into *warnings.
TriangleMesh load(const fs::path& p, std::vector<std::string>* warnings = nullptr) {
    ObjLoadOptions options;
    std::vector<std::string> ignored;
    options.warnings = warnings ? warnings : &ignored;
    return load_obj(p, options);
}

/// The message of the librt::Error load_obj throws, or "" if it does not throw.
std::string load_error(const fs::path& p) {
    try {
        (void)load(p);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

float total_area(const TriangleMesh& m) {
    float a = 0.0f;
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        a += 0.5f * glm::length(area_normal(m.triangle(i)));
    }
    return a;
}

bool contains(const std::string& haystack, const std::string& needle) {
    return haystack.find(needle) != std::string::npos;
}

const char* kSquareVerts =
    "v 0 0 0\n"
    "v 1 0 0\n"
    "v 1 1 0\n"
    "v 0 1 0\n";

}  // namespace

TEST(Obj, StanfordBunnyCountsAndBounds) {
    LIBRT_REQUIRE_DATA_FILE(path, "stanford-bunny.obj");
    std::vector<std::string> warnings;
    const TriangleMesh m = load(path, &warnings);
    EXPECT_EQ(m.vertex_count(), 35947u);  // unused vertices are kept
    EXPECT_EQ(m.triangle_count(), 69451u);
    EXPECT_TRUE(m.normals.empty());
    EXPECT_TRUE(m.uvs.empty());
    EXPECT_EQ(m.material_ids.size(), m.triangle_count());
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0].name, "default");
    EXPECT_TRUE(warnings.empty());
    // The scan is about 0.155 x 0.154 x 0.121 units, y up, standing on y = 0.033.
    const BBox b = m.bounds();
    EXPECT_NEAR(b.lo.x, -0.0947f, 1e-3f);
    EXPECT_NEAR(b.hi.x, 0.0610f, 1e-3f);
    EXPECT_NEAR(b.lo.y, 0.0330f, 1e-3f);
    EXPECT_NEAR(b.hi.y, 0.1873f, 1e-3f);
    EXPECT_NEAR(b.lo.z, -0.0619f, 1e-3f);
    EXPECT_NEAR(b.hi.z, 0.0588f, 1e-3f);
}

TEST(Obj, TriangleIndicesAreZeroBasedAndKeepWinding) {
    TempDir dir;
    const TriangleMesh m = load(dir.write("tri.obj", std::string(kSquareVerts) + "f 1 2 3\n"));
    EXPECT_EQ(m.vertex_count(), 4u);
    ASSERT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
}

TEST(Obj, QuadsAndPolygonsAreTriangulated) {
    TempDir dir;
    // A quad, a pentagon, a concave L-shaped hexagon (area 3) and a concave dart whose first
    // corner cannot see the others (a fan from it would fold over), all facing +z.
    const TriangleMesh m =
        load(dir.write("poly.obj", std::string(kSquareVerts) + "f 1 2 3 4\n"
                                                               "v 10 0 0\nv 12 0 0\nv 13 1 0\n"
                                                               "v 11 2 0\nv 9 1 0\n"
                                                               "f 5 6 7 8 9\n"
                                                               "v 20 0 0\nv 22 0 0\nv 22 1 0\n"
                                                               "v 21 1 0\nv 21 2 0\nv 20 2 0\n"
                                                               "f 10 11 12 13 14 15\n"
                                                               "v 30 0 0\nv 32 1 0\nv 34 0 0\n"
                                                               "v 32 3 0\n"
                                                               "f 16 17 18 19\n"));
    EXPECT_EQ(m.triangle_count(), 2u + 3u + 4u + 2u);  // n - 2 each
    // Pentagon and dart areas by the shoelace formula: 5 and 4.
    EXPECT_NEAR(total_area(m), 1.0f + 5.0f + 3.0f + 4.0f, 1e-5f);
    for (std::size_t i = 0; i < m.triangle_count(); ++i) {
        EXPECT_GT(area_normal(m.triangle(i)).z, 0.0f) << "triangle " << i;
    }
}

TEST(Obj, ZeroAreaPolygonIsSkippedWithAWarning) {
    TempDir dir;
    std::vector<std::string> warnings;
    const TriangleMesh m = load(dir.write("flat.obj",
                                          "v 0 0 0\nv 1 0 0\nv 2 0 0\nv 3 0 0\n"
                                          "v 0 1 0\n"
                                          "f 1 2 3 4\nf 1 2 5\n"),
                                &warnings);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_EQ(m.material_ids.size(), 1u);
    ASSERT_EQ(warnings.size(), 1u);
    EXPECT_TRUE(contains(warnings[0], "flat.obj")) << warnings[0];
    EXPECT_TRUE(contains(warnings[0], "skipped")) << warnings[0];
}

TEST(Obj, NegativeIndicesAreRelative) {
    TempDir dir;
    const TriangleMesh m = load(dir.write("rel.obj",
                                          "v 0 0 0\nv 1 0 0\nv 0 1 0\n"
                                          "vt 0 0\nvt 1 0\nvt 0 1\n"
                                          "f -3/-3 -2/-2 -1/-1\n"
                                          "v 5 5 5\n"
                                          "f -4 -3 -1\n"));
    ASSERT_EQ(m.triangle_count(), 2u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(m.positions[m.triangles[1].z], glm::vec3(5, 5, 5));
    ASSERT_EQ(m.uvs.size(), m.vertex_count());
    EXPECT_EQ(m.uvs[m.triangles[0].y], glm::vec2(1, 0));
}

TEST(Obj, TripletsAreUnifiedIntoVertices) {
    TempDir dir;
    // Two faces of a box edge: positions 2 and 3 are shared, but with different normals,
    // so they must split; the repeated triplet 1/1/1 must not.
    const TriangleMesh m = load(dir.write("split.obj",
                                          "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 1 0 -1\n"
                                          "vt 0 0\nvt 1 0\nvt 1 1\n"
                                          "vn 0 0 1\nvn 1 0 0\n"
                                          "f 1/1/1 2/2/1 3/3/1\n"
                                          "f 1/1/1 3/3/1 2/2/1\n"
                                          "f 2/1/2 4/2/2 3/3/2\n"));
    EXPECT_EQ(m.vertex_count(), 4u + 2u);  // 2/1/2 and 3/3/2 are new; 4/2/2 claims slot 3
    ASSERT_EQ(m.normals.size(), m.vertex_count());
    ASSERT_EQ(m.uvs.size(), m.vertex_count());
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(m.triangles[1], glm::uvec3(0, 2, 1));
    // Every corner gets exactly the attributes its triplet named.
    const glm::uvec3 t = m.triangles[2];
    EXPECT_EQ(m.positions[t.x], glm::vec3(1, 0, 0));
    EXPECT_EQ(m.positions[t.y], glm::vec3(1, 0, -1));
    EXPECT_EQ(m.positions[t.z], glm::vec3(1, 1, 0));
    for (int k = 0; k < 3; ++k) EXPECT_EQ(m.normals[t[k]], glm::vec3(1, 0, 0));
    EXPECT_EQ(m.uvs[t.x], glm::vec2(0, 0));
    EXPECT_EQ(m.uvs[t.y], glm::vec2(1, 0));
    EXPECT_EQ(m.uvs[t.z], glm::vec2(1, 1));
    EXPECT_EQ(m.normals[1], glm::vec3(0, 0, 1));
    EXPECT_NE(t.x, 1u);
    EXPECT_NE(t.z, 2u);
}

TEST(Obj, OptionsDropAttributesAndTransform) {
    TempDir dir;
    const fs::path p = dir.write("opt.obj",
                                 "v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\n"
                                 "vn 0 0 1\nvn 0 1 0\n"
                                 "f 1/1/1 2/2/1 3/1/1\nf 1/2/2 3/1/2 2/2/2\n");
    EXPECT_EQ(load(p).vertex_count(), 6u);  // the second face's three triplets are all new
    ObjLoadOptions options;
    std::vector<std::string> warnings;
    options.warnings = &warnings;
    options.load_normals = false;
    options.load_uvs = false;
    const TriangleMesh bare = load_obj(p, options);
    EXPECT_EQ(bare.vertex_count(), 3u);
    EXPECT_TRUE(bare.normals.empty());
    EXPECT_TRUE(bare.uvs.empty());

    options = {};
    options.warnings = &warnings;
    options.transform = make_transform({2, 1, 1}, {90, 0, 0}, {0, 0, 1});
    const TriangleMesh moved = load_obj(p, options);
    EXPECT_NEAR(glm::distance(moved.positions[1], glm::vec3(2, 0, 1)), 0.0f, 1e-6f);
    EXPECT_NEAR(moved.normals[0].y, -1.0f, 1e-6f);  // +z rotated about x by 90 degrees
}

TEST(Obj, MissingNormalsAreComputedFromFaces) {
    TempDir dir;
    const TriangleMesh m = load(dir.write("mixed.obj",
                                          "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\n"
                                          "vn 0 0 1\n"
                                          "f 1//1 2//1 3//1\nf 2 4 3\n"));
    ASSERT_EQ(m.normals.size(), m.vertex_count());
    EXPECT_EQ(m.normals[m.triangles[1].y], glm::vec3(0, 0, 1));  // vertex 4 had none
}

TEST(Obj, MaterialsAreReadFromTheMtl) {
    TempDir dir;
    dir.write("scene.mtl",
              "newmtl red\n"
              "Kd 0.8 0.1 0.1\nKs 0.2 0.3 0.4\nKe 1 2 3\nNi 1.5\nd 0.25\n"
              "illum 7\nmap_Kd textures/wood.png\n"
              "newmtl plain\nKd 0.5 0.5 0.5\n");
    const TriangleMesh m =
        load(dir.write("scene.obj", "mtllib scene.mtl\n" + std::string(kSquareVerts) +
                                        "f 1 2 3\n"
                                        "usemtl plain\nf 1 3 4\n"
                                        "usemtl red\nf 2 3 4 1\n"));
    ASSERT_EQ(m.materials.size(), 3u);  // red, plain, and the default for the first face
    const MeshMaterial& red = m.materials[0];
    EXPECT_EQ(red.name, "red");
    EXPECT_EQ(red.diffuse, glm::vec3(0.8f, 0.1f, 0.1f));
    EXPECT_EQ(red.specular, glm::vec3(0.2f, 0.3f, 0.4f));
    EXPECT_EQ(red.emission, glm::vec3(1, 2, 3));
    EXPECT_FLOAT_EQ(red.ior, 1.5f);
    EXPECT_FLOAT_EQ(red.dissolve, 0.25f);
    EXPECT_EQ(red.illum, 7);
    EXPECT_EQ(fs::path(red.diffuse_texture), dir.path() / "textures" / "wood.png");
    EXPECT_TRUE(m.materials[1].diffuse_texture.empty());
    EXPECT_EQ(m.materials[2].name, "default");
    EXPECT_EQ(m.material_ids, (std::vector<std::uint32_t>{2, 1, 0, 0}));
}

TEST(Obj, MissingMtlIsAWarningNotAnError) {
    TempDir dir;
    std::vector<std::string> warnings;
    const fs::path p = dir.write(
        "nomtl.obj", "mtllib absent.mtl\n" + std::string(kSquareVerts) + "usemtl red\nf 1 2 3\n");
    const TriangleMesh m = load(p, &warnings);
    EXPECT_EQ(m.triangle_count(), 1u);
    ASSERT_EQ(m.materials.size(), 1u);
    EXPECT_EQ(m.materials[0].name, "default");
    EXPECT_EQ(m.material_ids, (std::vector<std::uint32_t>{0}));
    bool named = false;
    for (const std::string& w : warnings) {
        EXPECT_TRUE(contains(w, "nomtl.obj")) << w;
        named = named || contains(w, "absent.mtl");
    }
    EXPECT_TRUE(named);

    // Without a warnings vector the caller does not want them: librt never prints.
    ::testing::internal::CaptureStderr();
    (void)load_obj(p);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

TEST(Obj, OutOfRangeIndicesNameFileAndFace) {
    TempDir dir;
    const std::string msg =
        load_error(dir.write("range.obj", std::string(kSquareVerts) + "f 1 2 3\nf 1 2 7\n"));
    EXPECT_TRUE(contains(msg, "range.obj")) << msg;
    EXPECT_TRUE(contains(msg, "face 2")) << msg;
    EXPECT_TRUE(contains(msg, "7")) << msg;
    // tinyobjloader would drop such a quad or read outside its arrays for an n-gon.
    for (const char* face :
         {"f 1 2 3 9\n", "f 1 2 3 4 9\n", "f -5 1 2\n", "f 1/4 2/1 3/1\n", "f 1//2 2//1 3//1\n"}) {
        const std::string text = std::string(kSquareVerts) + "vt 0 0\nvn 0 0 1\n" + face;
        const std::string m = load_error(dir.write("bad.obj", text));
        EXPECT_TRUE(contains(m, "bad.obj")) << face << " -> " << m;
        EXPECT_TRUE(contains(m, "face 1")) << face << " -> " << m;
    }
}

TEST(Obj, ZeroIndexIsAnErrorNamingTheFile) {
    TempDir dir;
    const std::string msg =
        load_error(dir.write("zero.obj", std::string(kSquareVerts) + "f 1 2 3\nf 0 1 2\n"));
    EXPECT_TRUE(contains(msg, "zero.obj")) << msg;
    EXPECT_TRUE(contains(msg, "zero.obj:6:")) << msg;  // file:line
}

TEST(Obj, MissingFileAndDirectoryAreErrorsNamingThePath) {
    TempDir dir;
    const fs::path missing = dir.path() / "nope.obj";
    std::string msg = load_error(missing);
    EXPECT_TRUE(contains(msg, missing.string())) << msg;
    EXPECT_TRUE(contains(msg, "no such file")) << msg;
    msg = load_error(dir.path());
    EXPECT_TRUE(contains(msg, dir.path().string())) << msg;
    EXPECT_TRUE(contains(msg, "directory")) << msg;
}

TEST(Obj, SaveThenLoadRoundTrips) {
    TempDir dir;
    dir.write("tex/checker.png", "");
    TriangleMesh m;
    m.positions = {{0.1f, 0.2f, 0.3f}, {1.0f / 3.0f, 0, 0}, {0, 1e-7f, -2.5f}, {7, 8, 9}};
    m.normals = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}, glm::normalize(glm::vec3(1, 2, 3))};
    m.uvs = {{0, 0}, {0.25f, 0.5f}, {1, 1}, {0.1f, 0.9f}};
    m.triangles = {{0, 1, 2}, {2, 1, 3}, {3, 0, 2}};
    MeshMaterial shiny;
    shiny.name = "shiny";
    shiny.diffuse = {0.1f, 0.2f, 0.3f};
    shiny.specular = glm::vec3(0.9f);
    shiny.emission = {4, 5, 6};
    shiny.ior = 1.33f;
    shiny.dissolve = 0.5f;
    shiny.illum = 3;
    shiny.diffuse_texture = (dir.path() / "tex" / "checker.png").string();
    MeshMaterial matte;
    matte.name = "matte";
    m.materials = {shiny, matte};
    m.material_ids = {1, 0, 1};

    const fs::path p = dir.path() / "out" / "round.obj";
    fs::create_directories(p.parent_path());
    save_obj(m, p);
    EXPECT_TRUE(fs::exists(dir.path() / "out" / "round.mtl"));
    EXPECT_EQ(std::distance(fs::directory_iterator(p.parent_path()), fs::directory_iterator()),
              2);  // no temporary files left behind
    // The texture lies beside out/, outside the saved OBJ's tree: a file we trust.
    ObjLoadOptions trusted;
    trusted.allow_outside_files = true;
    const TriangleMesh r = load_obj(p, trusted);
    EXPECT_EQ(r.positions, m.positions);
    EXPECT_EQ(r.normals, m.normals);
    EXPECT_EQ(r.uvs, m.uvs);
    EXPECT_EQ(r.triangles, m.triangles);
    EXPECT_EQ(r.material_ids, m.material_ids);
    ASSERT_EQ(r.materials.size(), 2u);
    for (std::size_t i = 0; i < 2; ++i) {
        EXPECT_EQ(r.materials[i].name, m.materials[i].name);
        EXPECT_EQ(r.materials[i].diffuse, m.materials[i].diffuse);
        EXPECT_EQ(r.materials[i].specular, m.materials[i].specular);
        EXPECT_EQ(r.materials[i].emission, m.materials[i].emission);
        EXPECT_EQ(r.materials[i].ior, m.materials[i].ior);
        EXPECT_EQ(r.materials[i].dissolve, m.materials[i].dissolve);
        EXPECT_EQ(r.materials[i].illum, m.materials[i].illum);
    }
    EXPECT_TRUE(fs::equivalent(r.materials[0].diffuse_texture, shiny.diffuse_texture));

    // A bare mesh: positions and triangles only, no MTL.
    TriangleMesh bare;
    bare.positions = m.positions;
    bare.triangles = m.triangles;
    const fs::path q = dir.path() / "bare.obj";
    save_obj(bare, q);
    EXPECT_FALSE(fs::exists(dir.path() / "bare.mtl"));
    const TriangleMesh rb = load(q);
    EXPECT_EQ(rb.positions, bare.positions);
    EXPECT_EQ(rb.triangles, bare.triangles);
    EXPECT_TRUE(rb.normals.empty());
}

TEST(Obj, SaveRejectsInvalidMeshesAndUnwritablePaths) {
    TempDir dir;
    TriangleMesh m;
    m.positions = {{0, 0, 0}};
    m.triangles = {{0, 0, 1}};
    EXPECT_THROW(save_obj(m, dir.path() / "invalid.obj"), Error);
    m.triangles = {{0, 0, 0}};
    EXPECT_THROW(save_obj(m, dir.path() / "no" / "such" / "dir.obj"), Error);
}
