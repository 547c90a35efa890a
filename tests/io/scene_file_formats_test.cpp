// The checklist for a new scene format (docs/architecture.md, "Adding a scene format"),
// checked over every row of scene_file_formats(): its extensions are well formed and its
// own, load_scene_file reaches its loader through each of them in any case, and the
// unknown-format message lists them all.

#include "io/temp_dir_test.h"

#include <librt/core/error.h>
#include <librt/loader/scene_file.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <fstream>
#include <set>
#include <string>

namespace librt {
namespace {

using SceneFileFormats = testing::TempDirTest;

/// The message load_scene_file throws for `path` ("" when it loads).
std::string load_error(const std::filesystem::path& path) {
    try {
        (void)load_scene_file(path);
    } catch (const Error& e) {
        return e.what();
    }
    return "";
}

TEST(SceneFileFormatsTable, EachFormatHasANameALoaderAndExtensionsOfItsOwn) {
    ASSERT_FALSE(scene_file_formats().empty());
    std::set<std::string> seen;
    for (const SceneFileFormat& f : scene_file_formats()) {
        SCOPED_TRACE(f.name);
        EXPECT_FALSE(f.name.empty());
        EXPECT_NE(f.load, nullptr);
        ASSERT_FALSE(f.extensions.empty());
        for (const std::string& ext : f.extensions) {
            // Lower case with the dot: load_scene_file compares lower_extension's result.
            ASSERT_GE(ext.size(), 2u) << ext;
            EXPECT_EQ(ext[0], '.') << ext;
            EXPECT_TRUE(std::none_of(ext.begin(), ext.end(), [](unsigned char c) {
                return std::isupper(c) != 0;
            })) << ext;
            EXPECT_TRUE(seen.insert(ext).second) << ext << " belongs to two formats";
        }
    }
}

TEST_F(SceneFileFormats, EveryExtensionReachesItsFormatsLoaderInAnyCase) {
    for (const SceneFileFormat& f : scene_file_formats()) {
        for (const std::string& ext : f.extensions) {
            std::string upper = ext;
            std::transform(upper.begin(), upper.end(), upper.begin(),
                           [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
            for (const std::string& e : {ext, upper}) {
                // Not a scene in any format: the loader refuses it, naming the file.
                const std::filesystem::path p = dir_ / ("broken" + e);
                std::ofstream(p, std::ios::binary) << "\x01\x02 not a scene \x7f";
                const std::string msg = load_error(p);
                SCOPED_TRACE(f.name + ", " + e + ": " + msg);
                EXPECT_NE(msg.find(p.string()), std::string::npos);
                EXPECT_EQ(msg.find("unknown scene format"), std::string::npos);
                // The format's loader gives the same error when called directly.
                std::string direct;
                try {
                    (void)f.load(p, {});
                } catch (const Error& error) {
                    direct = error.what();
                }
                EXPECT_EQ(direct, msg);
            }
        }
    }
}

TEST_F(SceneFileFormats, AnUnknownExtensionIsRefusedNamingEveryKnownOne) {
    const std::filesystem::path p = dir_ / "scene.ply";
    std::ofstream(p) << "ply\n";
    const std::string msg = load_error(p);
    EXPECT_NE(msg.find(p.string()), std::string::npos) << msg;
    EXPECT_NE(msg.find("unknown scene format '.ply'"), std::string::npos) << msg;
    for (const SceneFileFormat& f : scene_file_formats())
        for (const std::string& ext : f.extensions)
            EXPECT_NE(msg.find(ext), std::string::npos) << ext << " missing from: " << msg;
}

}  // namespace
}  // namespace librt
