// Bad OBJ input: every case either loads (with a warning naming file and line where
// something was dropped) or throws librt::Error "path:line: what". See the table in
// docs/robustness.md.

#include "robustness/obj_input_util.h"
#include "robustness/robustness_util.h"

#include <librt/obj/obj.h>
#include <librt/obj/obj_materials.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

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

/// The error loading `text` (written as name) gives; checks it names the file and line.
std::string load_error(const ScratchDir& dir, const std::string& name, const std::string& text,
                       int line) {
    const fs::path p = dir.write(name, text);
    std::vector<std::string> warnings;
    const std::string msg = error_of([&] { (void)load(p, warnings); });
    EXPECT_TRUE(has(msg, p.string() + ":" + std::to_string(line) + ":"))
        << "expected " << name << ":" << line << " in: " << msg;
    return msg;
}

}  // namespace

TEST(BadObj, MissingFileNamesThePath) {
    ScratchDir dir;
    const fs::path p = dir.path() / "absent.obj";
    std::vector<std::string> w;
    const std::string msg = error_of([&] { (void)load(p, w); });
    EXPECT_TRUE(has(msg, p.string())) << msg;
    EXPECT_TRUE(has(msg, "no such file")) << msg;
}

TEST(BadObj, DirectoryNamesThePath) {
    ScratchDir dir;
    fs::create_directory(dir.path() / "folder.obj");
    std::vector<std::string> w;
    const std::string msg = error_of([&] { (void)load(dir.path() / "folder.obj", w); });
    EXPECT_TRUE(has(msg, "folder.obj")) << msg;
    EXPECT_TRUE(has(msg, "is a directory")) << msg;
}

TEST(BadObj, UnreadableFileNamesThePath) {
    ScratchDir dir;
    const fs::path p = dir.write("locked.obj", kTriangle + "f 1 2 3\n");
    fs::permissions(p, fs::perms::none);
    LIBRT_SKIP_IF_PERMISSIONS_BYPASSED(p);
    std::vector<std::string> w;
    const std::string msg = error_of([&] { (void)load(p, w); });
    EXPECT_TRUE(has(msg, p.string())) << msg;
    EXPECT_TRUE(has(msg, "cannot open for reading")) << msg;
    EXPECT_TRUE(has(msg, "Permission denied")) << msg;
}

TEST(BadObj, EmptyFileGivesAnEmptyMeshAndAWarning) {
    ScratchDir dir;
    for (const char* text : {"", "\n\n", "# only a comment\n", "   \t  \n"}) {
        std::vector<std::string> w;
        const TriangleMesh m = load(dir.write("empty.obj", text), w);
        EXPECT_EQ(m.triangle_count(), 0u);
        EXPECT_EQ(m.vertex_count(), 0u);
        EXPECT_TRUE(has(joined(w), "empty.obj: no faces")) << joined(w);
    }
    // An empty mesh is a valid scene object that nothing hits.
    std::vector<std::string> w;
    Scene scene;
    const auto grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    (void)scene.add_mesh(load(dir.write("empty.obj", ""), w), grey);
    scene.commit();
    Hit hit;
    EXPECT_FALSE(scene.intersect(Ray{{0, 0, 5}, {0, 0, -1}}, hit));
}

TEST(BadObj, MalformedNumbersNameFileAndLine) {
    ScratchDir dir;
    struct Case {
        const char* text;
        int line;
        const char* says;
    };
    const Case cases[] = {
        {"v 0 0 0\nv 1 abc 0\n", 2, "malformed number 'abc'"},
        {"v 0 0 0\nv 1,5 2 0\n", 2, "malformed number '1,5'"},
        {"v 0 0 0\nv 1 2 3x\n", 2, "malformed number '3x'"},
        {"v nan 0 0\n", 1, "nan is not finite"},
        {"v 0 0 0\n\nv inf 0 0\n", 3, "inf is not finite"},
        {"v 1e999 0 0\n", 1, "1e999 is not finite"},
        {"v 1e39 0 0\n", 1, "not finite in single precision"},  // fits a double, not a float
        {"v 1 2\n", 1, "'v' needs 3 to 7 numbers, found 2"},
        {"v\n", 1, "found 0"},
        {"v 1 2 3 4 5 6 7 8\n", 1, "found 8"},
        {"vn 0 1\n", 1, "'vn' needs 3 numbers, found 2"},
        {"vt\n", 1, "'vt' needs 1 to 3 numbers, found 0"},
        {"vt 0.5 -nan\n", 1, "not finite"},
    };
    for (const Case& c : cases) {
        const std::string msg = load_error(dir, "numbers.obj", c.text, c.line);
        EXPECT_TRUE(has(msg, c.says)) << c.text << " -> " << msg;
    }
    // Accepted spellings: signs, exponents, w and vertex colours, trailing comments.
    std::vector<std::string> w;
    const TriangleMesh m = load(dir.write("fine.obj",
                                          "v +1 -2.5e0 .5\nv 1 0 0 1\n"
                                          "v 0 1 0 0.5 0.5 0.5 # colour\n"
                                          "f 1 2 3\n"),
                                w);
    ASSERT_EQ(m.vertex_count(), 3u);
    EXPECT_EQ(m.positions[0], glm::vec3(1.0f, -2.5f, 0.5f));
}

TEST(BadObj, IndexOutOfRangeNamesFileAndLine) {
    ScratchDir dir;
    std::string msg = load_error(dir, "range.obj", kTriangle + "f 1 2 3\nf 1 2 4\n", 5);
    EXPECT_TRUE(has(msg, "position index 4 is out of range (the file has 3)")) << msg;
    msg = load_error(dir, "range.obj", kTriangle + "vt 0 0\nf 1/1 2/2 3/1\n", 5);
    EXPECT_TRUE(has(msg, "texture coordinate index 2 is out of range")) << msg;
    msg = load_error(dir, "range.obj", kTriangle + "vn 0 0 1\nf 1//1 2//1 3//9\n", 5);
    EXPECT_TRUE(has(msg, "normal index 9 is out of range")) << msg;
    // An index beyond int.
    msg = load_error(dir, "range.obj", kTriangle + "f 1 2 99999999999999999999\n", 4);
    EXPECT_TRUE(has(msg, "out of range")) << msg;
    msg = load_error(dir, "range.obj", kTriangle + "f 1 2 2147483648\n", 4);
    EXPECT_TRUE(has(msg, "out of range")) << msg;
    // A face may refer to positions defined further down (legal OBJ).
    std::vector<std::string> w;
    const TriangleMesh m = load(dir.write("forward.obj", "f 1 2 3\n" + kTriangle), w);
    EXPECT_EQ(m.triangle_count(), 1u);
    // With uvs not loaded, vt indices are not range-checked (the syntax still is).
    ObjLoadOptions no_uvs;
    no_uvs.load_uvs = false;
    no_uvs.warnings = &w;
    EXPECT_EQ(load_obj(dir.write("uv.obj", kTriangle + "f 1/7 2/7 3/7\n"), no_uvs).triangle_count(),
              1u);
}

TEST(BadObj, ZeroIndexNamesFileAndLine) {
    ScratchDir dir;
    for (const char* face : {"f 0 1 2\n", "f 1/0 2/1 3/1\n", "f 1//0 2//1 3//1\n"}) {
        const std::string msg =
            load_error(dir, "zero.obj", kTriangle + "vt 0 0\nvn 0 0 1\n" + face, 6);
        EXPECT_TRUE(has(msg, "index 0 (OBJ indices start at 1)")) << face << " -> " << msg;
    }
}

TEST(BadObj, NegativeIndicesResolveOrNameTheLine) {
    ScratchDir dir;
    std::vector<std::string> w;
    // Relative to the positions defined so far: -1 is the latest.
    const TriangleMesh m =
        load(dir.write("rel.obj", kTriangle + "f -3 -2 -1\nv 5 5 5\nf -4 -3 -1\n"), w);
    ASSERT_EQ(m.triangle_count(), 2u);
    EXPECT_EQ(m.triangles[0], glm::uvec3(0, 1, 2));
    EXPECT_EQ(m.triangles[1], glm::uvec3(0, 1, 3));
    const std::string msg = load_error(dir, "rel.obj", kTriangle + "f 1 2 -4\n", 4);
    EXPECT_TRUE(has(msg, "relative position index -4 reaches before the first position")) << msg;
    const std::string uv = load_error(dir, "rel.obj", kTriangle + "vt 0 0\nf 1/-2 2/1 3/1\n", 5);
    EXPECT_TRUE(has(uv, "relative texture coordinate index -2")) << uv;
}

TEST(BadObj, MalformedCornersNameTheLine) {
    ScratchDir dir;
    for (const char* face : {"f 1 2 3.5\n", "f 1 2 x\n", "f 1/1/1/1 2 3\n", "f 1/ 2 3\n",
                             "f 1// 2 3\n", "f /1 2 3\n", "f 1 2 3-\n", "f 1 2 0x3\n"}) {
        const std::string msg = load_error(dir, "corner.obj", kTriangle + "vt 0 0\n" + face, 5);
        EXPECT_TRUE(has(msg, "face 1, corner '")) << face << " -> " << msg;
    }
}

TEST(BadObj, FacesOfFewerThanThreeCornersAreIgnoredWithAWarning) {
    ScratchDir dir;
    std::vector<std::string> w;
    const TriangleMesh m = load(dir.write("short.obj", kTriangle + "f 1 2\nf 3\nf\nf 1 2 3\n"), w);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_TRUE(has(joined(w), "short.obj: line 4: 3 face(s) of fewer than 3 corners ignored"))
        << joined(w);
}

TEST(BadObj, LinesAndPointsOnlyGiveAnEmptyMeshAndWarnings) {
    ScratchDir dir;
    std::vector<std::string> w;
    const TriangleMesh m = load(dir.write("wire.obj", kTriangle + "l 1 2 3 1\np 1 2\np 3\n"), w);
    EXPECT_EQ(m.triangle_count(), 0u);
    EXPECT_EQ(m.vertex_count(), 3u);  // positions are kept (unused ones included)
    const std::string all = joined(w);
    EXPECT_TRUE(has(all, "wire.obj: line 4: 3 line/point statement(s) ignored")) << all;
    EXPECT_TRUE(has(all, "no faces")) << all;
}

TEST(BadObj, LineEndingsAndNoFinalNewline) {
    ScratchDir dir;
    for (const char* text : {"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3",            // no final newline
                             "v 0 0 0\r\nv 1 0 0\r\nv 0 1 0\r\nf 1 2 3\r\n",  // CRLF
                             "v 0 0 0\rv 1 0 0\rv 0 1 0\rf 1 2 3\r"}) {       // old Mac CR
        std::vector<std::string> w;
        EXPECT_EQ(load(dir.write("endings.obj", text), w).triangle_count(), 1u) << text;
        EXPECT_TRUE(w.empty()) << joined(w);
    }
    // Line numbers count CR, LF and CRLF alike.
    const std::string msg = load_error(dir, "endings.obj", "v 0 0 0\r\nv 1 0 0\rv 0 x 0\n", 3);
    EXPECT_TRUE(has(msg, "'x'")) << msg;
}

TEST(BadObj, VeryLongLines) {
    ScratchDir dir;
    const std::string mb(std::size_t{1} << 20, '7');
    std::vector<std::string> w;
    // A 1 MB comment, group name and unknown statement: read, the last one warned about.
    const TriangleMesh m = load(dir.write("long.obj", "#" + mb + "\ng " + mb + "\n" + kTriangle +
                                                          "f 1 2 3\n" + "junk" + mb + "\n"),
                                w);
    EXPECT_EQ(m.triangle_count(), 1u);
    EXPECT_TRUE(has(joined(w), "long.obj: line 7: 1 unknown statement(s) ignored")) << joined(w);
    EXPECT_LT(joined(w).size(), 1000u);  // the 1 MB keyword is not copied into the message
    // A 1 MB number: out of float range, named with its line (and shortened).
    std::string msg = load_error(dir, "long.obj", kTriangle + "v 1 1 " + mb + "\n", 4);
    EXPECT_TRUE(has(msg, "not finite")) << msg.substr(0, 200);
    EXPECT_LT(msg.size(), 1000u);
    // A 1 MB face: more corners than tinyobjloader can count.
    std::string face = "f";
    while (face.size() < (std::size_t{1} << 20)) face += " 1 2 3";
    msg = load_error(dir, "long.obj", kTriangle + face + "\n", 4);
    EXPECT_TRUE(has(msg, "corners (at most 255 are supported)")) << msg;
}

TEST(BadObj, NulBytesNameTheLine) {
    ScratchDir dir;
    const std::string text = kTriangle + std::string("f 1 2\0 3\n", 9);
    const std::string msg = load_error(dir, "nul.obj", text, 4);
    EXPECT_TRUE(has(msg, "NUL byte in column 6")) << msg;
    // Binary junk, e.g. a PNG given as an OBJ.
    const std::string png("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16);
    EXPECT_TRUE(has(load_error(dir, "image.obj", png, 3), "NUL byte")) << png;
}

TEST(BadObj, Utf16IsRejectedNamingTheEncoding) {
    ScratchDir dir;
    // "v 0 0 0\n" in UTF-16 LE with and without a byte order mark.
    std::string utf16;
    for (const char c : std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")) {
        utf16 += c;
        utf16 += '\0';
    }
    const std::string with_bom = load_error(dir, "utf16.obj", "\xff\xfe" + utf16, 1);
    EXPECT_TRUE(has(with_bom, "UTF-16 byte order mark")) << with_bom;
    const std::string big_endian = load_error(dir, "utf16.obj", "\xfe\xff" + utf16, 1);
    EXPECT_TRUE(has(big_endian, "UTF-16")) << big_endian;
    const std::string without = load_error(dir, "utf16.obj", utf16, 1);
    EXPECT_TRUE(has(without, "NUL byte")) << without;
}

TEST(BadObj, Utf8JunkIsWarnedAboutAndItsByteOrderMarkSkipped) {
    ScratchDir dir;
    std::vector<std::string> w;
    // Unknown statements in UTF-8 (and invalid UTF-8) are ignored with one warning.
    const TriangleMesh m = load(dir.write("utf8.obj", kTriangle + "\xc3\xa9t\xc3\xa9 1 2\n"
                                                                  "\xe2\x82\xac\xff\xfe\n"
                                                                  "g caf\xc3\xa9\nf 1 2 3\n"),
                                w);
    EXPECT_EQ(m.triangle_count(), 1u);
    const std::string all = joined(w);
    EXPECT_TRUE(has(all,
                    "utf8.obj: line 4: 2 unknown statement(s) ignored (first here: "
                    "'\\xc3\\xa9t\\xc3\\xa9')"))
        << all;
    // A UTF-8 byte order mark would otherwise hide the first vertex from tinyobjloader.
    w.clear();
    const TriangleMesh bom =
        load(dir.write("bom.obj", "\xef\xbb\xbf" + kTriangle + "f 1 2 3\n"), w);
    ASSERT_EQ(bom.vertex_count(), 3u);
    EXPECT_EQ(bom.triangle_count(), 1u);
    EXPECT_TRUE(w.empty()) << joined(w);
}

// The scene side of a missing MTL (Obj.MissingMtlIsAWarningNotAnError covers the loader):
// the faces get the loader's "default" material.
TEST(BadObj, MissingMtlGivesTheDefaultMaterial) {
    ScratchDir dir;
    std::vector<std::string> w;
    const TriangleMesh m =
        load(dir.write("nomtl.obj", "mtllib gone.mtl\nusemtl red\n" + kTriangle + "f 1 2 3\n"), w);
    EXPECT_TRUE(has(joined(w), "gone.mtl")) << joined(w);
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.25f)));
    (void)add_mesh_with_mtl(scene, m, fallback);
    scene.commit();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, hit));
    // The MTL loader's "default" material maps to a new diffuse material of Kd 0.8, not the
    // fallback: a missing MTL behaves like a file without usemtl.
    EXPECT_EQ(scene.material(hit).kind, MaterialKind::Diffuse);
    EXPECT_EQ(scene.material(hit).albedo, glm::vec3(0.8f));
    EXPECT_EQ(scene.material(hit).albedo_texture, -1);
}

TEST(BadObj, MissingTextureIsAWarningAndKeepsKd) {
    ScratchDir dir;
    dir.write("tex.mtl", "newmtl painted\nKd 0.1 0.2 0.3\nmap_Kd no_such_texture.png\n");
    std::vector<std::string> w;
    const TriangleMesh m =
        load(dir.write("tex.obj", "mtllib tex.mtl\nusemtl painted\n" + kTriangle +
                                      "vt 0 0\n"
                                      "f 1/1 2/1 3/1\n"),
             w);
    ASSERT_EQ(m.materials.size(), 1u);
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    // A warning in the returned list, not on stderr (the library never prints).
    ::testing::internal::CaptureStderr();
    const MtlMeshResult added = add_mesh_with_mtl(scene, m, fallback);
    EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
    ASSERT_EQ(added.warnings.size(), 1u);
    const std::string& warning = added.warnings[0];
    EXPECT_TRUE(has(warning, "painted")) << warning;
    EXPECT_TRUE(has(warning, "no_such_texture.png")) << warning;
    scene.commit();
    Hit hit;
    ASSERT_TRUE(scene.intersect(Ray{{0.2f, 0.2f, 1.0f}, {0, 0, -1}}, hit));
    EXPECT_EQ(scene.material(hit).albedo_texture, -1);
    EXPECT_EQ(scene.albedo(hit), glm::vec3(0.1f, 0.2f, 0.3f));
}

TEST(BadObj, ImpossibleMtlValuesNameTheMaterial) {
    ScratchDir dir;
    dir.write("bright.mtl", "newmtl too_bright\nKd 1.5 0 0\n");
    std::vector<std::string> w;
    const TriangleMesh m = load(
        dir.write("bright.obj", "mtllib bright.mtl\nusemtl too_bright\n" + kTriangle + "f 1 2 3\n"),
        w);
    Scene scene;
    const auto fallback = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const std::string msg = error_of([&] { (void)add_mesh_with_mtl(scene, m, fallback); });
    EXPECT_TRUE(has(msg, "MTL material 'too_bright'")) << msg;
    EXPECT_TRUE(has(msg, "albedo = (1.5, 0, 0)")) << msg;
}
