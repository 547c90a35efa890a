#include "io/temp_dir_test.h"

#include <librt/core/error.h>
#include <librt/io/image_io.h>

#include <gtest/gtest.h>

#include <stb/stb_image.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::read_all;
namespace fs = std::filesystem;

namespace {

class ImageIoTest : public librt::testing::TempDirTest {};

Image test_image() {
    Image image(5, 3);
    for (int y = 0; y < image.height; ++y) {
        for (int x = 0; x < image.width; ++x) {
            image.at(x, y) = {0.1f * static_cast<float>(x), 0.3f * static_cast<float>(y),
                              static_cast<float>(x * y) + 1e-7f};
        }
    }
    image.at(0, 0) = {std::numeric_limits<float>::infinity(), -2.5f, 1e30f};
    image.at(1, 0) = {std::numeric_limits<float>::denorm_min(), -0.0f, 123456.789f};
    return image;
}

}  // namespace

TEST_F(ImageIoTest, PfmRoundTripIsBitExact) {
    const Image image = test_image();
    const fs::path path = dir_ / "a.pfm";
    write_pfm(path, image);
    const Image back = read_pfm(path);
    ASSERT_EQ(back.width, image.width);
    ASSERT_EQ(back.height, image.height);
    EXPECT_EQ(std::memcmp(back.pixels.data(), image.pixels.data(),
                          image.pixels.size() * sizeof(glm::vec3)),
              0);
    EXPECT_EQ(entries(), 1u);  // no temporary left behind
}

TEST_F(ImageIoTest, PfmLayoutIsLittleEndianBottomRowFirst) {
    Image image(1, 2);
    image.at(0, 0) = {1.0f, 2.0f, 3.0f};  // top row
    image.at(0, 1) = {4.0f, 5.0f, 6.0f};  // bottom row
    write_pfm(dir_ / "b.pfm", image);
    const std::string bytes = read_all(dir_ / "b.pfm");
    const std::string header = "PF\n1 2\n-1.0\n";
    ASSERT_EQ(bytes.size(), header.size() + 24);
    EXPECT_EQ(bytes.substr(0, header.size()), header);
    // 4.0f = 0x40800000, little-endian: 00 00 80 40.
    EXPECT_EQ(bytes.substr(header.size(), 4), std::string("\x00\x00\x80\x40", 4));
}

TEST_F(ImageIoTest, ReadsBigEndianAndGreyscalePfm) {
    {
        std::ofstream out(dir_ / "g.pfm", std::ios::binary);
        out << "Pf\n2 1\n1.0\n";
        out.write("\x3f\x80\x00\x00\x40\x00\x00\x00", 8);  // 1.0f, 2.0f big-endian
    }
    const Image image = read_pfm(dir_ / "g.pfm");
    ASSERT_EQ(image.width, 2);
    EXPECT_EQ(image.at(0, 0), glm::vec3(1.0f));
    EXPECT_EQ(image.at(1, 0), glm::vec3(2.0f));
}

TEST_F(ImageIoTest, MalformedPfmNamesTheFile) {
    const fs::path path = dir_ / "bad.pfm";
    for (const std::string& content : {std::string("P6\n1 1\n255\n"), std::string("PF\n0 1\n-1\n"),
                                       std::string("PF\n2 2\n-1\nabc"),
                                       std::string("PF\n1 1\n0\n            "), std::string("")}) {
        {
            std::ofstream out(path, std::ios::binary);
            out << content;
        }
        try {
            (void)read_pfm(path);
            ADD_FAILURE() << "accepted: " << content;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find("bad.pfm"), std::string::npos) << e.what();
        }
    }
    EXPECT_THROW((void)read_pfm(dir_ / "missing.pfm"), Error);
}

TEST_F(ImageIoTest, PngIsToneMapped) {
    Image image(2, 2);
    image.at(0, 0) = {1.0f, 0.5f, 0.0f};
    image.at(1, 1) = {NAN, 2.0f, -1.0f};
    const fs::path path = dir_ / "c.png";
    write_image(path, image, ToneMap{});
    int w = 0, h = 0, n = 0;
    unsigned char* data = stbi_load(path.string().c_str(), &w, &h, &n, 3);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(w, 2);
    EXPECT_EQ(h, 2);
    EXPECT_EQ(data[0], 255);
    EXPECT_EQ(data[1], 187);
    EXPECT_EQ(data[2], 0);
    EXPECT_EQ(data[9], 0);
    EXPECT_EQ(data[10], 255);
    EXPECT_EQ(data[11], 0);
    stbi_image_free(data);
}

TEST_F(ImageIoTest, HdrIsWrittenAndReadable) {
    Image image(3, 2);
    image.at(2, 1) = {0.5f, 1.0f, 4.0f};
    const fs::path path = dir_ / "d.hdr";
    write_image(path, image, ToneMap{2.0f, 0.45f});  // exposure scales, no gamma
    int w = 0, h = 0, n = 0;
    float* data = stbi_loadf(path.string().c_str(), &w, &h, &n, 3);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(w, 3);
    EXPECT_NEAR(data[15], 1.0f, 0.01f);
    EXPECT_NEAR(data[16], 2.0f, 0.02f);
    EXPECT_NEAR(data[17], 8.0f, 0.08f);
    stbi_image_free(data);
}

TEST_F(ImageIoTest, UnknownExtensionNamesThePath) {
    try {
        write_image(dir_ / "e.jpg", Image(1, 1), ToneMap{});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("e.jpg"), std::string::npos) << e.what();
    }
    EXPECT_EQ(entries(), 0u);
}

TEST_F(ImageIoTest, MissingDirectoryThrowsAndLeavesNothing) {
    const fs::path path = dir_ / "no_such_dir" / "f.png";
    for (const char* ext : {".png", ".pfm", ".hdr"}) {
        fs::path p = path;
        p.replace_extension(ext);
        try {
            write_image(p, Image(2, 2), ToneMap{});
            ADD_FAILURE() << p;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(p.filename().string()), std::string::npos)
                << e.what();
        }
    }
    EXPECT_FALSE(fs::exists(dir_ / "no_such_dir"));
    EXPECT_EQ(entries(), 0u);
}

TEST_F(ImageIoTest, ExistingFileIsReplacedWhole) {
    const fs::path path = dir_ / "g.pfm";
    {
        std::ofstream out(path, std::ios::binary);
        out << "old contents that are longer than nothing";
    }
    const auto old_inode_holder = fs::status(path).type();
    ASSERT_EQ(old_inode_holder, fs::file_type::regular);
    // A reader holding the old file open keeps seeing the old bytes: the new file is a
    // different inode renamed over the name, not the old one rewritten in place.
    std::ifstream old_reader(path, std::ios::binary);
    write_pfm(path, test_image());
    const std::string old_bytes{std::istreambuf_iterator<char>(old_reader),
                                std::istreambuf_iterator<char>()};
    EXPECT_EQ(old_bytes, "old contents that are longer than nothing");
    const Image back = read_pfm(path);
    EXPECT_EQ(back.width, 5);
    EXPECT_EQ(entries(), 1u);
}

TEST_F(ImageIoTest, FailedWriteKeepsTheOldFile) {
    // Writing onto a path that is a non-empty directory fails at the rename: the
    // directory and its content are untouched and no temporary is left behind.
    const fs::path path = dir_ / "h.png";
    fs::create_directories(path / "inside");
    EXPECT_THROW(write_png(path, Image(2, 2)), Error);
    EXPECT_TRUE(fs::is_directory(path / "inside"));
    EXPECT_EQ(entries(), 1u);
}

TEST_F(ImageIoTest, EmptyImageIsRejected) {
    EXPECT_THROW(write_pfm(dir_ / "i.pfm", Image()), Error);
    EXPECT_EQ(entries(), 0u);
}

// write_display_png (issue 42 item 6): 16 bits per channel and straight alpha, read back by
// stb_image: each value is round(v * 65535) (or 255), big-endian in the file as PNG wants;
// other depths and an alpha of the wrong size are errors naming the file, writing nothing.
TEST_F(ImageIoTest, DisplayPngHas16BitsAndAlpha) {
    Image image(3, 1);
    image.at(0, 0) = {0.0f, 0.5f, 1.0f};
    image.at(1, 0) = {0.25f, 1.0f / 65535.0f, 2.0f};  // above 1: clamped
    image.at(2, 0) = {NAN, -1.0f, 0.75f};             // NaN and below 0: 0
    const std::vector<float> alpha = {1.0f, 0.5f, 0.0f};
    const fs::path path = dir_ / "deep.png";
    write_display_png(path, image, 16, &alpha);
    int w = 0, h = 0, n = 0;
    stbi_us* data = stbi_load_16(path.string().c_str(), &w, &h, &n, 4);
    ASSERT_NE(data, nullptr);
    EXPECT_EQ(w, 3);
    EXPECT_EQ(h, 1);
    EXPECT_EQ(n, 4);
    const std::vector<int> expected = {0,     32768, 65535, 65535,  // pixel 0
                                       16384, 1,     65535, 32768,  // pixel 1
                                       0,     0,     49151, 0};     // pixel 2
    for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(int(data[i]), expected[i]) << i;
    stbi_image_free(data);

    const fs::path rgb = dir_ / "rgb8.png";
    write_display_png(rgb, image, 8);
    unsigned char* bytes = stbi_load(rgb.string().c_str(), &w, &h, &n, 0);
    ASSERT_NE(bytes, nullptr);
    EXPECT_EQ(n, 3);
    EXPECT_EQ(int(bytes[1]), 128);  // round(0.5 * 255)
    EXPECT_EQ(int(bytes[3]), 64);   // round(0.25 * 255)
    stbi_image_free(bytes);

    const fs::path bad = dir_ / "bad.png";
    try {
        write_display_png(bad, image, 12);
        FAIL() << "12 bits accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("bad.png"), std::string::npos) << e.what();
        EXPECT_NE(std::string(e.what()).find("bits = 12"), std::string::npos) << e.what();
    }
    const std::vector<float> short_alpha = {1.0f};
    EXPECT_THROW(write_display_png(bad, image, 8, &short_alpha), Error);
    EXPECT_FALSE(fs::exists(bad));
}
