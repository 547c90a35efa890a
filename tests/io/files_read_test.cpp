// LoadedScene::files_read: every file a scene was made from, each once, with the digest of
// the bytes the loader used. The ranks of an MPI job compare these (rt_render), so a .bin,
// an image or an MTL file that differs between machines must be listed, and its digest must
// be the file's own (file_digest, read separately here), never that of a changed copy.

#include "io/gltf_test_util.h"
#include "io/temp_dir_test.h"

#include <librt/io/file_digest.h>
#include <librt/loader/scene_file.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

namespace librt {
namespace {

namespace fs = std::filesystem;
using FilesRead = testing::TempDirTest;

/// The entries of `files` that lead to `p` (the same file, however spelled).
std::size_t count_of(const std::vector<FileRead>& files, const fs::path& p) {
    return std::size_t(std::count_if(files.begin(), files.end(), [&](const FileRead& f) {
        std::error_code ec;
        return fs::equivalent(f.path, p, ec);
    }));
}

/// The entry of `files` for `p`; fails the test when there is none.
FileRead entry_for(const std::vector<FileRead>& files, const fs::path& p) {
    for (const FileRead& f : files) {
        std::error_code ec;
        if (fs::equivalent(f.path, p, ec)) return f;
    }
    ADD_FAILURE() << p << " is not listed";
    return {};
}

/// Its digest is the file's, as file_digest reads it.
void expect_digest_of_file(const FileRead& f, const fs::path& p) {
    const FileDigest expected = file_digest(p);
    EXPECT_EQ(f.digest.fnv1a64, expected.fnv1a64) << p;
    EXPECT_EQ(f.digest.bytes, expected.bytes) << p;
}

TEST_F(FilesRead, AGltfListsItselfItsBinAndTheImagesItsTexturesUseEachOnce) {
    testing::GltfBuilder b = testing::one_triangle();
    fs::create_directories(dir_ / "maps");
    testing::write_file(dir_ / "maps" / "wood.png", testing::tiny_png());
    testing::write_file(dir_ / "spare.png", testing::tiny_png());
    // Image 1 names wood.png again (decoded once, listed once); image 2 is used by no
    // texture (not read); image 3 is missing (a warning, nothing listed).
    b.doc["images"] = {{{"uri", "maps/wood.png"}},
                       {{"uri", "maps/../maps/wood.png"}},
                       {{"uri", "spare.png"}},
                       {{"uri", "missing.png"}}};
    b.doc["textures"] = {{{"source", 0}}, {{"source", 1}}, {{"source", 3}}};
    b.doc["materials"] = {
        {{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}},
    };
    b.doc["meshes"][0]["primitives"][0]["material"] = 0;
    const fs::path bin = dir_ / "geometry.bin";
    testing::write_file(bin, b.bin);
    const fs::path gltf = dir_ / "scene.gltf";
    testing::write_file(gltf, b.with_buffer("geometry.bin").dump());

    const LoadedScene loaded = load_scene_file(gltf);
    const std::vector<FileRead>& files = loaded.files_read;
    ASSERT_EQ(files.size(), 3u);
    // The scene file first, by the path it was given.
    EXPECT_EQ(files[0].path, gltf);
    expect_digest_of_file(files[0], gltf);
    EXPECT_EQ(count_of(files, bin), 1u);
    expect_digest_of_file(entry_for(files, bin), bin);
    EXPECT_EQ(count_of(files, dir_ / "maps" / "wood.png"), 1u);
    expect_digest_of_file(entry_for(files, dir_ / "maps" / "wood.png"), dir_ / "maps" / "wood.png");
    EXPECT_EQ(count_of(files, dir_ / "spare.png"), 0u);

    // Another .bin of the same size under the same name: the same JSON, another digest.
    std::string other = b.bin;
    other[0] = char(other[0] ^ 0x40);
    testing::write_file(bin, other);
    const LoadedScene changed = load_scene_file(gltf);
    ASSERT_EQ(changed.files_read.size(), 3u);
    EXPECT_EQ(changed.files_read[0].digest.fnv1a64, files[0].digest.fnv1a64);
    expect_digest_of_file(entry_for(changed.files_read, bin), bin);
    EXPECT_NE(entry_for(changed.files_read, bin).digest.fnv1a64,
              entry_for(files, bin).digest.fnv1a64);
}

TEST_F(FilesRead, AGlbListsOnlyItselfWhenItHoldsEverything) {
    const fs::path glb = dir_ / "scene.glb";
    testing::write_file(glb, testing::one_triangle().glb());
    const LoadedScene loaded = load_scene_file(glb);
    ASSERT_EQ(loaded.files_read.size(), 1u);
    EXPECT_EQ(loaded.files_read[0].path, glb);
    expect_digest_of_file(loaded.files_read[0], glb);
}

TEST_F(FilesRead, AnObjListsItselfItsMtlAndItsTexture) {
    testing::write_file(dir_ / "wood.png", testing::tiny_png());
    testing::write_file(dir_ / "broken.png", "not an image at all");
    // Two materials share wood.png (read once); broken.png does not decode (a warning,
    // the material keeps its Kd: not listed).
    testing::write_file(dir_ / "looks.mtl",
                        "newmtl a\nKd 0.5 0.5 0.5\nmap_Kd wood.png\n"
                        "newmtl b\nKd 0.2 0.2 0.2\nmap_Kd wood.png\n"
                        "newmtl c\nKd 0.7 0.7 0.7\nmap_Kd broken.png\n");
    // A trailing comment, which the loader blanks in its copy of the text: the digest is
    // of the file as written all the same.
    const fs::path obj = dir_ / "mesh.obj";
    testing::write_file(obj,
                        "mtllib looks.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
                        "usemtl a\nf 1/1 2/2 3/3 # the only face\n");
    const LoadedScene loaded = load_scene_file(obj);
    const std::vector<FileRead>& files = loaded.files_read;
    ASSERT_EQ(files.size(), 3u);
    EXPECT_EQ(files[0].path, obj);
    expect_digest_of_file(files[0], obj);
    EXPECT_EQ(count_of(files, dir_ / "looks.mtl"), 1u);
    expect_digest_of_file(entry_for(files, dir_ / "looks.mtl"), dir_ / "looks.mtl");
    EXPECT_EQ(count_of(files, dir_ / "wood.png"), 1u);
    expect_digest_of_file(entry_for(files, dir_ / "wood.png"), dir_ / "wood.png");
    EXPECT_EQ(count_of(files, dir_ / "broken.png"), 0u);
    EXPECT_TRUE(std::any_of(
        loaded.warnings.begin(), loaded.warnings.end(),
        [](const std::string& w) { return w.find("broken.png") != std::string::npos; }));
}

TEST_F(FilesRead, AnObjWithoutItsMtlListsOnlyItself) {
    const fs::path obj = dir_ / "mesh.obj";
    testing::write_file(obj, "mtllib gone.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
    const LoadedScene loaded = load_scene_file(obj);
    ASSERT_EQ(loaded.files_read.size(), 1u);
    EXPECT_EQ(loaded.files_read[0].path, obj);
}

}  // namespace
}  // namespace librt
