// Inputs the fuzzers found (kept in tests/fuzz/corpus/*/regression-*), replayed through
// the same calls as the fuzz targets: each must end in a result or a librt::Error,
// quickly and without a large allocation.

#include "robustness/robustness_util.h"

#include <librt/io/image_io.h>
#include <librt/io/texture_io.h>

#include <gtest/gtest.h>

#include <chrono>
#include <string>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;

namespace {

double seconds_to_load_texture(const std::filesystem::path& p, std::string& message) {
    const auto start = std::chrono::steady_clock::now();
    message = error_of([&] { (void)load_texture(p); });
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

// image_fuzz, out of memory: a 14-byte PPM header claiming 2000000 x 90 texels made stb
// allocate 540 MB and librt 2.2 GB of floats for pixels that were never there.
TEST(FuzzRegression, ImageOomPpmHeaderClaimingHugeSize) {
    ScratchDir dir;
    const auto p = dir.write("regression-oom-ppm-2000000x90.ppm", "P6\n2000000 90\n");
    std::string msg;
    EXPECT_LT(seconds_to_load_texture(p, msg), 1.0);
    EXPECT_TRUE(has(msg, "2000000 x 90 texels, more than the limit")) << msg;
    EXPECT_TRUE(has(error_of([&] { (void)read_pfm(p); }), "not a valid PFM"));
}

// image_fuzz, slow unit: a 19-byte PPM claiming 20000 x 2000 texels (under the limit)
// made stb allocate 120 MB and return it uninitialised (its PNM reader ignores short
// reads); now refused as truncated before stb decodes.
TEST(FuzzRegression, ImageSlowTruncatedPpm) {
    ScratchDir dir;
    const auto p = dir.write("regression-slow-ppm-20000x2000.ppm",
                             std::string("P6\n20000 2000\x1e\n690\n", 19));
    std::string msg;
    EXPECT_LT(seconds_to_load_texture(p, msg), 1.0);
    EXPECT_TRUE(has(msg, "regression-slow-ppm-20000x2000.ppm")) << msg;
}

// image_fuzz, slow unit (35 s, 660 MB under ASan): an 83-byte TGA header claiming
// 6168 x 6168 texels, which stb decoded as zeros one byte at a time. Now refused: a file
// cannot hold more than 4096 texels per byte.
TEST(FuzzRegression, ImageSlowTgaClaimingHugeSize) {
    ScratchDir dir;
    std::string tga("\x00\x00\x02\x02\x00\x00", 6);
    tga += std::string(62, '\x18');  // colour map spec, origin, 0x1818 x 0x1818, ...
    tga += std::string("\x00\x00\x00\x00=00Pf\x00\x18\x00\x00\x00\x01", 15);
    ASSERT_EQ(tga.size(), 83u);
    const auto p = dir.write("regression-slow-tga-6168x6168.tga", tga);
    std::string msg;
    EXPECT_LT(seconds_to_load_texture(p, msg), 1.0);
    EXPECT_TRUE(has(msg, "6168 x 6168 texels in a file of 83 bytes")) << msg;
}
