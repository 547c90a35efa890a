// write_image's .exr (through io/exr.h) and check_image_path, the check apps run before
// they load or render anything.

#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/io/exr.h>
#include <librt/io/image_io.h>

#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <string>

using namespace librt;
using librt::testing::ScratchDir;

TEST(ImagePath, WriteImageWritesExrLinearTimesExposure) {
    ScratchDir dir;
    Image image(3, 2);
    image.at(1, 1) = {0.25f, 0.5f, 2.0f};
    const auto path = dir.path() / "out.EXR";
    write_image(path, image, ToneMap{2.0f, 0.45f});
    const ImageLayers back = read_exr(path);
    ASSERT_EQ(back.beauty.width, 3);
    ASSERT_EQ(back.beauty.height, 2);
    // Half floats hold these exactly: 0.5, 1 and 4 are powers of two.
    EXPECT_EQ(back.beauty.at(1, 1).x, 0.5f);
    EXPECT_EQ(back.beauty.at(1, 1).z, 4.0f);
    EXPECT_EQ(back.beauty.at(0, 0).y, 0.0f);
}

TEST(ImagePath, CheckImagePathRefusesWhatWriteImageCannotWrite) {
    ScratchDir dir;
    EXPECT_NO_THROW(check_image_path(dir.path() / "a.png"));
    EXPECT_NO_THROW(check_image_path(dir.path() / "a.Exr"));
    auto message = [](const std::filesystem::path& p) {
        try {
            check_image_path(p);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    EXPECT_NE(message(dir.path() / "a.jpg").find("unknown image format"), std::string::npos);
    EXPECT_NE(message(dir.path() / "no_such_dir" / "a.png").find("no directory"),
              std::string::npos);
    EXPECT_NE(message(dir.path()).find("unknown image format"), std::string::npos);
    std::filesystem::create_directory(dir.path() / "d.png");
    EXPECT_NE(message(dir.path() / "d.png").find("a directory"), std::string::npos);
    EXPECT_TRUE(std::filesystem::is_empty(dir.path() / "d.png"));
}

TEST(ImagePath, AnOverLongPathSaysSoNotNoDirectory) {
    ScratchDir dir;
    auto message = [](const std::filesystem::path& p) {
        try {
            check_image_path(p);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string too_long(300, 'a');  // over NAME_MAX (255) on Linux file systems
    const std::string reason = std::strerror(ENAMETOOLONG);
    // A directory component too long: the directory is not missing, its name is too long.
    const std::string in_dir = message(dir.path() / too_long / "x.png");
    EXPECT_NE(in_dir.find(reason), std::string::npos) << in_dir;
    EXPECT_EQ(in_dir.find("no directory"), std::string::npos) << in_dir;
    // The file's own name too long: said before rendering, not when the file is created.
    const std::string file = message(dir.path() / (too_long + ".png"));
    EXPECT_NE(file.find(reason), std::string::npos) << file;
    // A path component that is a regular file.
    std::ofstream(dir.path() / "plain").put('x');
    const std::string not_dir = message(dir.path() / "plain" / "x.png");
    EXPECT_EQ(not_dir.find("no directory"), std::string::npos) << not_dir;
    EXPECT_NE(not_dir.find(std::strerror(ENOTDIR)), std::string::npos) << not_dir;
}
