#include <librt/core/error.h>
#include <librt/core/image.h>
#include <librt/core/tone_map.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace librt;

TEST(ToneMap, ReportExposureIs255ToTheMinusOneOverGamma) {
    EXPECT_FLOAT_EQ(kReportExposure, static_cast<float>(std::pow(255.0, -1.0 / 0.45)));
}

TEST(ToneMap, ChannelValues) {
    const ToneMap unit;  // exposure 1, gamma 0.45
    EXPECT_EQ(tone_map_channel(0.0f, unit), 0);
    EXPECT_EQ(tone_map_channel(1.0f, unit), 255);
    EXPECT_EQ(tone_map_channel(7.0f, unit), 255);
    EXPECT_EQ(tone_map_channel(-1.0f, unit), 0);
    EXPECT_EQ(tone_map_channel(std::numeric_limits<float>::infinity(), unit), 255);
    EXPECT_EQ(tone_map_channel(-std::numeric_limits<float>::infinity(), unit), 0);
    EXPECT_EQ(tone_map_channel(std::numeric_limits<float>::quiet_NaN(), unit), 0);
    // 255 * 0.5^0.45 = 186.6 -> 187.
    EXPECT_EQ(tone_map_channel(0.5f, unit), 187);
    const ToneMap linear{2.0f, 1.0f};
    EXPECT_EQ(tone_map_channel(0.25f, linear), 128);  // 255 * 0.5 = 127.5 rounds up
}

TEST(ToneMap, ReportExposureMatchesTheReportsFormula) {
    const ToneMap report{kReportExposure, 0.45f};
    // The report: min(255, L^0.45), truncated to a byte; ours rounds to nearest.
    for (const float l : {0.0f, 1.0f, 100.0f, 2500.0f, 40000.0f, 150000.0f, 222000.0f, 1e7f}) {
        const double expected = std::min(255.0, std::pow(static_cast<double>(l), 0.45));
        EXPECT_NEAR(tone_map_channel(l, report), expected, 0.5 + 1e-3) << "L = " << l;
    }
}

TEST(ToneMap, ToRgb8IsRowMajorRgb) {
    Image image(2, 1);
    image.at(0, 0) = {1.0f, 0.0f, 0.0f};
    image.at(1, 0) = {0.0f, 0.0f, NAN};
    const std::vector<std::uint8_t> rgb = to_rgb8(image, ToneMap{});
    ASSERT_EQ(rgb.size(), 6u);
    EXPECT_EQ(rgb, (std::vector<std::uint8_t>{255, 0, 0, 0, 0, 0}));
}

TEST(ToneMap, InvalidParametersAreNamed) {
    const Image image(1, 1);
    try {
        (void)to_rgb8(image, ToneMap{-1.0f, 0.45f});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("exposure = -1"), std::string::npos) << e.what();
    }
    try {
        (void)to_rgb8(image, ToneMap{1.0f, 0.0f});
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("gamma = 0"), std::string::npos) << e.what();
    }
}

TEST(Image, SizeIsCheckedBeforeAllocating) {
    const Image image(3, 2);
    EXPECT_EQ(image.pixels.size(), 6u);
    EXPECT_EQ(&image.at(2, 1), &image.pixels[5]);
    EXPECT_THROW(Image(-1, 4), Error);
    try {
        const Image huge(65536, 65536);  // 48 GiB
        ADD_FAILURE();
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("65536 x 65536"), std::string::npos) << e.what();
    }
}
