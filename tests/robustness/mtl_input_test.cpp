// Issue 10, defects 5 and 8 (the loader's side): MTL files are read as strictly as OBJ
// files, material names with spaces match, face lines may end in comments, Windows paths
// in map_Kd are found, and tinyobjloader's warnings come with a line, once.

#include "robustness/obj_input_util.h"
#include "robustness/robustness_util.h"

#include <librt/io/texture_io.h>
#include <librt/obj/obj.h>
#include <librt/obj/obj_materials.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::joined;
using librt::testing::ScratchDir;
namespace fs = std::filesystem;

namespace {

const std::string& kTriangle = librt::testing::kObjTriangle;
constexpr auto load = librt::testing::load_with_warnings;

/// The one material the triangle of `m.obj` (with `mtl` as its MTL) gets.
MeshMaterial material_of(const ScratchDir& dir, const std::string& mtl,
                         std::vector<std::string>& warnings, const std::string& use = "x") {
    dir.write("m.mtl", mtl);
    const TriangleMesh m =
        load(dir.write("m.obj", "mtllib m.mtl\nusemtl " + use + "\n" + kTriangle + "f 1 2 3\n"),
             warnings);
    EXPECT_EQ(m.material_ids.size(), 1u);
    return m.materials.at(m.material_ids.at(0));
}

/// The error loading an OBJ whose MTL is `mtl`.
std::string mtl_error(const ScratchDir& dir, const std::string& mtl) {
    dir.write("m.mtl", mtl);
    const fs::path obj = dir.write("m.obj", "mtllib m.mtl\nusemtl x\n" + kTriangle + "f 1 2 3\n");
    std::vector<std::string> warnings;
    return error_of([&] { (void)load(obj, warnings); });
}

}  // namespace

TEST(BadMtl, MaterialNamesWithSpacesMatch) {
    ScratchDir dir;
    std::vector<std::string> w;
    const MeshMaterial m =
        material_of(dir, "newmtl dark oak wood\nKd 0.1 0.2 0.3\n", w, "dark oak wood");
    EXPECT_EQ(m.name, "dark oak wood");
    EXPECT_EQ(m.diffuse, glm::vec3(0.1f, 0.2f, 0.3f));
    EXPECT_TRUE(w.empty()) << joined(w);
}

TEST(BadMtl, NumbersAreStrictAndNameFileAndLine) {
    ScratchDir dir;
    const std::string mtl = (dir.path() / "m.mtl").string();
    for (const auto& [text, expected] : std::vector<std::pair<std::string, std::string>>{
             {"newmtl x\nKd nan 0 0\n", ":2: 'Kd' number nan is not finite"},
             {"newmtl x\nKd abc\n", ":2: 'Kd' has a malformed number 'abc'"},
             {"newmtl x\nKd 0.5 0.5\n", ":2: 'Kd' needs 1 or 3 numbers, found 2"},
             {"newmtl x\n\nd nan\n", ":3: 'd' number nan is not finite"},
             {"newmtl x\nKs 1e39 0 0\n", ":2: 'Ks' number 1e39 is not finite"},
             {"newmtl x\nNi 1.5.2\n", ":2: 'Ni' has a malformed number '1.5.2'"},
             {"newmtl x\nillum 2.5\n", ":2: 'illum' needs an integer, found 2.5"},
         }) {
        const std::string msg = mtl_error(dir, text);
        EXPECT_TRUE(has(msg, mtl + expected)) << "for " << text << " got: " << msg;
    }
    // One number means grey; comments after numbers are allowed.
    std::vector<std::string> w;
    EXPECT_EQ(material_of(dir, "newmtl x\nKd 0.25 # grey\n", w).diffuse, glm::vec3(0.25f));
}

TEST(BadMtl, ReplacedValuesAreWarnedAbout) {
    ScratchDir dir;
    std::vector<std::string> w;
    // A glass with a negative index of refraction used to become 1.5 without a word.
    MeshMaterial m = material_of(dir, "newmtl x\nillum 7\nNi -2\n", w);
    EXPECT_EQ(m.ior, 1.5f);
    EXPECT_TRUE(has(joined(w), "m.mtl:1: material 'x': Ni -2 is not a valid index of refraction"))
        << joined(w);
    w.clear();
    m = material_of(dir, "newmtl x\nd 1.5\n", w);
    EXPECT_EQ(m.dissolve, 1.0f);
    EXPECT_TRUE(has(joined(w), "m.mtl:2: material 'x': d 1.5 is outside [0, 1]: using 1"))
        << joined(w);
}

TEST(BadObj, FaceLinesWithTrailingCommentsAreAccepted) {
    ScratchDir dir;
    std::vector<std::string> w;
    const TriangleMesh m = load(dir.write("c.obj",
                                          "v 0 0 0 # origin\nv 1 0 0\nv 0 1 0\n"
                                          "v 1 1 0\nf 1 2 3 # first\nf 2 4 3\t#second\n"),
                                w);
    EXPECT_EQ(m.triangle_count(), 2u);
    EXPECT_TRUE(w.empty()) << joined(w);
}

TEST(BadMtl, WindowsSeparatorsInTexturePathsAreNormalised) {
    ScratchDir dir;
    fs::create_directories(dir.path() / "tex");
    dir.write("tex/wood.ppm", std::string("P6\n1 1\n255\n\x80\x40\x20", 14));
    std::vector<std::string> w;
    const MeshMaterial m =
        material_of(dir, "newmtl x\nKd 0.5 0.5 0.5\nmap_Kd -s 2 2 1 -bm 1 .\\tex\\wood.ppm\n", w);
    EXPECT_EQ(m.diffuse_texture, (dir.path() / "tex" / "wood.ppm").string());
    EXPECT_EQ(load_texture(m.diffuse_texture).width(), 1);
    EXPECT_TRUE(w.empty()) << joined(w);
}

TEST(BadObj, UnknownMaterialIsWarnedOnceWithItsLine) {
    ScratchDir dir;
    dir.write("m.mtl", "newmtl known\nKd 1 1 1\n");
    std::vector<std::string> w;
    const TriangleMesh m =
        load(dir.write("u.obj", "mtllib m.mtl\n" + kTriangle +
                                    "usemtl missing\nf 1 2 3\nusemtl known\nf 1 2 3\n"
                                    "usemtl missing\nf 1 2 3\ng \n"),
             w);
    ASSERT_EQ(m.triangle_count(), 3u);
    EXPECT_EQ(m.materials[m.material_ids[0]].name, "default");
    EXPECT_EQ(m.materials[m.material_ids[1]].name, "known");
    EXPECT_EQ(m.materials[m.material_ids[2]].name, "default");
    const std::string all = joined(w);
    // tinyobjloader said "material [ 'missing' ] not found in .mtl" twice, with no line.
    EXPECT_EQ(std::count(w.begin(), w.end(),
                         (dir.path() / "u.obj").string() +
                             ": line 5: usemtl 'missing': no such material "
                             "in the MTL file(s); its faces get the default "
                             "material"),
              1)
        << all;
    EXPECT_FALSE(has(all, "not found in .mtl")) << all;
    EXPECT_TRUE(has(all, "u.obj: line 11: 'g' without a name")) << all;
    // Every warning names the file and a line (or is the file-wide "no faces" kind).
    for (const std::string& line : w) EXPECT_TRUE(has(line, "u.obj: line ")) << line;
}

TEST(BadObj, NumbersBelowDoubleRangeReadAsZero) {
    ScratchDir dir;
    std::vector<std::string> w;
    // 1e-400 underflows even a double; it used to be reported as "not finite".
    const TriangleMesh m =
        load(dir.write("u.obj", "v 1e-400 0 0\nv 1 0 0\nv 0 1 -1e-400\nf 1 2 3\n"), w);
    EXPECT_EQ(m.positions[0], glm::vec3(0.0f));
    EXPECT_EQ(m.positions[2], glm::vec3(0.0f, 1.0f, 0.0f));
    const std::string msg = error_of([&] { (void)load(dir.write("o.obj", "v 1e400 0 0\n"), w); });
    EXPECT_TRUE(has(msg, "o.obj:1: 'v' number 1e400 is not finite")) << msg;
}

TEST(BadMtl, MirrorReflectanceErrorsNameKs) {
    ScratchDir dir;
    std::vector<std::string> w;
    dir.write("m.mtl", "newmtl chrome\nillum 3\nKs 1.5 0 0\n");
    const TriangleMesh m =
        load(dir.write("m.obj", "mtllib m.mtl\nusemtl chrome\n" + kTriangle + "f 1 2 3\n"), w);
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    // It said "material albedo = (1.5, 0, 0)", a name the MTL does not use.
    const std::string msg = error_of([&] { (void)add_mesh_with_mtl(scene, m, fallback); });
    EXPECT_TRUE(has(msg, "MTL material 'chrome': Ks = (1.5, 0, 0)")) << msg;
    EXPECT_FALSE(has(msg, "albedo")) << msg;
}
