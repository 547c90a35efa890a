// Radiance .hdr files as untrusted input (issue 37, defect 6): a header claiming more
// texels than the data holds, data that ends early or that stb_image would misread. Every
// file is written here, byte by byte.

#include "robustness/robustness_util.h"

#include <librt/io/hdr_image.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;

namespace {

// ---- Radiance HDR (RGBE), as Greg Ward's format description (Graphics Gems II, "Real
// Pixels", and Radiance's color.c) lays it out.

std::string hdr_header(int w, int h) {
    return "#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y " + std::to_string(h) + " +X " +
           std::to_string(w) + "\n";
}

using Rgbe = std::array<std::uint8_t, 4>;

// A new-style run-length scanline: 2, 2, width (big-endian), then each component's bytes
// as runs (count 128 + n, then the value) of 3 or more equal bytes and dumps (count n,
// then n bytes) of the rest; n at most 127 and 128.
std::string rle_scanline(const std::vector<Rgbe>& texels) {
    const std::size_t w = texels.size();
    std::string out = {2, 2, char(w >> 8u), char(w & 0xFFu)};
    for (std::size_t c = 0; c < 4; ++c) {
        std::size_t x = 0;
        while (x < w) {
            std::size_t run = 1;
            while (x + run < w && run < 127 && texels[x + run][c] == texels[x][c]) ++run;
            if (run >= 3) {
                out += char(128 + run);
                out += char(texels[x][c]);
                x += run;
                continue;
            }
            std::size_t dump = 0;  // up to the next run of 3 or 128 bytes
            while (x + dump < w && dump < 128 &&
                   !(x + dump + 2 < w && texels[x + dump][c] == texels[x + dump + 1][c] &&
                     texels[x + dump][c] == texels[x + dump + 2][c]))
                ++dump;
            out += char(dump);
            for (std::size_t k = 0; k < dump; ++k) out += char(texels[x + k][c]);
            x += dump;
        }
    }
    return out;
}

std::string flat_scanline(const std::vector<Rgbe>& texels) {
    std::string out;
    for (const Rgbe& t : texels)
        for (std::uint8_t b : t) out += char(b);
    return out;
}

// An RGBE texel's value as stb_image decodes it: mantissa * 2^(exponent - 136).
float rgbe_value(std::uint8_t mantissa, std::uint8_t exponent) {
    return exponent == 0 ? 0.0f : std::ldexp(float(mantissa), int(exponent) - 136);
}

// Row y of a w-wide test image: a run of one colour, then texels that differ one from the
// next (dumps), so both kinds of run-length record appear.
std::vector<Rgbe> test_row(int w, int y) {
    std::vector<Rgbe> row(std::size_t(w), Rgbe{128, 64, 32, 129});  // (1, 0.5, 0.25)
    for (int x = w / 2; x < w; ++x)
        row[std::size_t(x)] = {std::uint8_t(128 + x), std::uint8_t(y), std::uint8_t(255 - x),
                               std::uint8_t(130 + x % 3)};
    return row;
}

void expect_test_image(const EnvironmentImage& image, int w, int h) {
    ASSERT_EQ(image.width, w);
    ASSERT_EQ(image.height, h);
    for (int y = 0; y < h; ++y) {
        const std::vector<Rgbe> row = test_row(w, y);
        for (int x = 0; x < w; ++x) {
            const Rgbe& t = row[std::size_t(x)];
            const glm::vec3 want(rgbe_value(t[0], t[3]), rgbe_value(t[1], t[3]),
                                 rgbe_value(t[2], t[3]));
            EXPECT_EQ(image.pixels[std::size_t(y * w + x)], want) << x << ", " << y;
        }
    }
}

}  // namespace

// Defect 6: a 100-byte file claiming 8192 x 8192 texels took 1.6 GB and 33 s and loaded
// as a black sky. Its data could hold at most a few scanlines.
TEST(BadHdr, HeaderClaimingMoreTexelsThanTheDataHoldsIsRefused) {
    ScratchDir dir;
    std::string bytes = hdr_header(8192, 8192);
    bytes += std::string{2, 2, 0x20, 0};  // one scanline's start, then nothing
    bytes.resize(100, '\0');
    const auto p = dir.write("claims_8192.hdr", bytes);
    const std::string msg = error_of([&] { (void)load_hdr_image(p); });
    EXPECT_TRUE(has(msg, p.string())) << msg;
    EXPECT_TRUE(has(msg, "8192 x 8192 texels in a file of 100 bytes")) << msg;
}

// The bound is the format's: width 8 to 32767 run-length encodes at no less than 8 bytes
// per 127 texels and 4 per scanline; other widths are flat, 4 bytes a texel.
TEST(BadHdr, ValidRunLengthAndFlatFilesLoadWithTheirValues) {
    ScratchDir dir;
    for (const int w : {16, 300, 4}) {
        const int h = 3;
        std::string bytes = hdr_header(w, h);
        for (int y = 0; y < h; ++y)
            bytes += w >= 8 ? rle_scanline(test_row(w, y)) : flat_scanline(test_row(w, y));
        const auto p = dir.write("valid_" + std::to_string(w) + ".hdr", bytes);
        SCOPED_TRACE(p.string());
        expect_test_image(load_hdr_image(p), w, h);
    }
    // A constant image: every scanline the shortest it can be (a run per 127 texels).
    std::string bytes = hdr_header(254, 2);
    for (int y = 0; y < 2; ++y)
        bytes += rle_scanline(std::vector<Rgbe>(254, Rgbe{128, 128, 128, 130}));
    ASSERT_EQ(bytes.size(), hdr_header(254, 2).size() + 2 * (4 + 4 * 2 * 2));
    const EnvironmentImage image = load_hdr_image(dir.write("constant.hdr", bytes));
    ASSERT_EQ(image.pixels.size(), 508u);
    EXPECT_EQ(image.pixels[507], glm::vec3(2.0f));  // 128 * 2^(130 - 136)
}

// A header that fits the file's size but data that ends early: stb_image returned a
// zero-filled image for a file cut at a scanline's end, and looped forever on one cut
// inside a scanline. Both are refused, as is a mix stb would misread.
TEST(BadHdr, TruncatedOrMisencodedDataIsRefused) {
    ScratchDir dir;
    const int w = 16, h = 8;
    std::string full = hdr_header(w, h);
    for (int y = 0; y < h; ++y) full += rle_scanline(test_row(w, y));
    ASSERT_NO_THROW((void)load_hdr_image(dir.write("full.hdr", full)));
    const std::size_t scanline = rle_scanline(test_row(w, 0)).size();
    const std::size_t start = hdr_header(w, h).size();

    const auto at_row = dir.write("cut_after_3_rows.hdr", full.substr(0, start + 3 * scanline));
    std::string msg = error_of([&] { (void)load_hdr_image(at_row); });
    EXPECT_TRUE(has(msg, at_row.string())) << msg;
    EXPECT_TRUE(has(msg, "truncated: the data ends in scanline 4 of 8")) << msg;

    const auto inside = dir.write("cut_inside_row_4.hdr", full.substr(0, start + 3 * scanline + 9));
    msg = error_of([&] { (void)load_hdr_image(inside); });
    EXPECT_TRUE(has(msg, inside.string())) << msg;
    EXPECT_TRUE(has(msg, "truncated: the data ends in scanline 4 of 8")) << msg;

    std::string mixed = full.substr(0, start + scanline) + flat_scanline(test_row(w, 1));
    mixed.resize(full.size(), '\x40');
    const auto mix = dir.write("mixed.hdr", mixed);
    msg = error_of([&] { (void)load_hdr_image(mix); });
    EXPECT_TRUE(has(msg, "scanline 2 is not run-length encoded")) << msg;

    std::string overrun = full;
    overrun[start + 4] = char(128 + 17);  // a run of 17 in a scanline of 16
    msg = error_of([&] { (void)load_hdr_image(dir.write("overrun.hdr", overrun)); });
    EXPECT_TRUE(has(msg, "overrun.hdr: scanline 1: a run past its end")) << msg;

    // Flat (width below 8): 4 bytes a texel; one short is truncated.
    std::string flat =
        hdr_header(4, 2) + flat_scanline(test_row(4, 0)) + flat_scanline(test_row(4, 1));
    flat.pop_back();
    msg = error_of([&] { (void)load_hdr_image(dir.write("flat.hdr", flat)); });
    EXPECT_TRUE(has(msg, "flat.hdr: the header claims 4 x 2 texels in a file of")) << msg;
}

namespace {

// A w x h image of one colour, run-length coded at its shortest: 4 + 8 ceil(w / 127)
// bytes a scanline, so a few megabytes decode to hundreds of millions of texels.
std::string constant_hdr(int w, int h, Rgbe colour) {
    std::string bytes = hdr_header(w, h);
    const std::string line = rle_scanline(std::vector<Rgbe>(std::size_t(w), colour));
    bytes.reserve(bytes.size() + line.size() * std::size_t(h));
    for (int y = 0; y < h; ++y) bytes += line;
    return bytes;
}

}  // namespace

// Issue 37, defect 2: loading may take 16 x the bytes read + 256 MiB. A valid 2 MB
// run-length file of 8192 x 4096 texels decoded to 805 MB of floats and as much again for
// the image (1.6 GB for 8192^2, measured in docs/robustness.md); it is refused from its
// header before stb allocates, the message giving the size, the cost and the bound.
TEST(BadHdr, ValidFileDecodingPastTheMemoryBoundIsRefused) {
    ScratchDir dir;
    const std::string bytes = constant_hdr(8192, 4096, Rgbe{128, 128, 128, 129});
    ASSERT_LT(bytes.size(), std::size_t{3} << 20u);
    const auto p = dir.write("big_sky.hdr", bytes);
    const std::uint64_t bound = 16 * std::uint64_t(bytes.size()) + (std::uint64_t{256} << 20u);
    const std::string msg = error_of([&] { (void)load_hdr_image(p); });
    EXPECT_TRUE(has(msg, "cannot load HDR image " + p.string() + ": 8192 x 4096 texels")) << msg;
    // 24 bytes a texel: stb's float RGB and the image made from it.
    EXPECT_TRUE(has(msg, "would take 805306368 bytes to decode, more than the " +
                             std::to_string(bound) + " a file of " + std::to_string(bytes.size()) +
                             " bytes may use"))
        << msg;
}

// The bound refuses only what exceeds it: a 2048 x 1024 sky (50 MB decoded) from a file of
// 140 KB, far more texels per byte than a photograph, still loads with its values.
TEST(BadHdr, ModerateRunLengthFileWithinTheBoundLoads) {
    ScratchDir dir;
    const std::string bytes = constant_hdr(2048, 1024, Rgbe{128, 64, 32, 131});
    ASSERT_LT(16 * bytes.size(), std::size_t{4} << 20u);
    const EnvironmentImage image = load_hdr_image(dir.write("sky.hdr", bytes));
    ASSERT_EQ(image.width, 2048);
    ASSERT_EQ(image.height, 1024);
    const glm::vec3 want(rgbe_value(128, 131), rgbe_value(64, 131), rgbe_value(32, 131));
    EXPECT_EQ(image.pixels.front(), want);
    EXPECT_EQ(image.pixels.back(), want);
}
