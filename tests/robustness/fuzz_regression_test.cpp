// Inputs the fuzzers found (kept in tests/fuzz/corpus/*/regression-*), replayed through
// the same calls as the fuzz targets: each must end in a result or a librt::Error, the
// error saying why it was refused before the large allocation or the slow decode (the
// refusal, not a measured time, is what is checked: the fuzzers' own time and memory
// limits find the slow inputs).

#include "robustness/robustness_util.h"

#include <librt/io/image_io.h>
#include <librt/io/texture_io.h>

#include <gtest/gtest.h>

#include <string>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;

// image_fuzz, out of memory: a 14-byte PPM header claiming 2000000 x 90 texels made stb
// allocate 540 MB and librt 2.2 GB of floats for pixels that were never there.
TEST(FuzzRegression, ImageOomPpmHeaderClaimingHugeSize) {
    ScratchDir dir;
    const auto p = dir.write("regression-oom-ppm-2000000x90.ppm", "P6\n2000000 90\n");
    const std::string msg = error_of([&] { (void)load_texture(p); });
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
    const std::string msg = error_of([&] { (void)load_texture(p); });
    EXPECT_TRUE(has(msg,
                    "20000x2000.ppm: the header claims 20000 x 2000 texels in a file of 19 "
                    "bytes (corrupt or truncated)"))
        << msg;
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
    const std::string msg = error_of([&] { (void)load_texture(p); });
    EXPECT_TRUE(has(msg, "6168 x 6168 texels in a file of 83 bytes")) << msg;
}
