// ImageTexture: sRGB and linear decoding, the three glTF wrap modes and bilinear weights at
// exact texel positions, nearest filtering, alpha, and the KHR_texture_transform map.

#include <librt/core/error.h>
#include <librt/gltf/gltf.h>
#include <librt/material/texture.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace librt {
namespace {

// The IEC 61966-2-1 decoding written out in double, independently of srgb_to_linear.
double srgb_reference(int byte) {
    const double c = byte / 255.0;
    return c <= 0.04045 ? c / 12.92 : std::pow((c + 0.055) / 1.055, 2.4);
}

// A width x 1 texture whose texel i has red = i (exact in float), from linear floats.
ImageTexture ramp(int width, const TextureSampling& s) {
    std::vector<glm::vec3> t;
    for (int i = 0; i < width; ++i) t.emplace_back(float(i), 0.0f, 0.0f);
    ImageTexture tex(width, 1, std::move(t));
    tex.set_sampling(s);
    return tex;
}

// u of the centre of texel i (any integer) of an n-wide texture.
float centre(int i, int n) { return (float(i) + 0.5f) / float(n); }

TEST(TextureDecoding, SrgbBytesDecodeByTheStandardCurveAndLinearBytesDivideBy255) {
    std::vector<std::uint8_t> rgba;
    for (int b = 0; b < 256; ++b) rgba.insert(rgba.end(), {std::uint8_t(b), 0, 255, 255});
    const ImageTexture srgb = ImageTexture::from_rgba8(256, 1, rgba, ColorSpace::Srgb);
    const ImageTexture linear = ImageTexture::from_rgba8(256, 1, rgba, ColorSpace::Linear);
    for (int b = 0; b < 256; ++b) {
        // float rounding of the reference: a few ulps of the value.
        EXPECT_NEAR(srgb.texel(b, 0).x, srgb_reference(b), 1e-6 * (1.0 + srgb_reference(b))) << b;
        EXPECT_FLOAT_EQ(linear.texel(b, 0).x, float(b) / 255.0f) << b;
        EXPECT_EQ(srgb.texel(b, 0).z, 1.0f);
    }
    // Spot values of the curve: 0.5 (128/255 ~ 0.50196) decodes to ~0.2158; 10/255 is on
    // the linear segment.
    EXPECT_NEAR(srgb.texel(128, 0).x, 0.21586, 1e-5);
    EXPECT_FLOAT_EQ(srgb.texel(10, 0).x, float(10.0 / 255.0 / 12.92));
    EXPECT_FALSE(srgb.has_alpha());  // every alpha byte 255
}

TEST(TextureDecoding, AlphaIsKeptLinearWhenSomeTexelIsNotOpaque) {
    const std::vector<std::uint8_t> rgba{255, 255, 255, 0, 255, 255, 255, 51};
    const ImageTexture t = ImageTexture::from_rgba8(
        2, 1, rgba, ColorSpace::Srgb,
        {TextureWrap::ClampToEdge, TextureWrap::ClampToEdge, TextureFilter::Nearest});
    ASSERT_TRUE(t.has_alpha());
    EXPECT_EQ(t.lookup_alpha({0.25f, 0.5f}), 0.0f);
    EXPECT_FLOAT_EQ(t.lookup_alpha({0.75f, 0.5f}), 0.2f);
    EXPECT_THROW(
        (void)ImageTexture::from_rgba8(2, 1, std::vector<std::uint8_t>(7, 0), ColorSpace::Linear),
        Error);
    // Without alpha, lookup_alpha is 1 everywhere.
    EXPECT_EQ(ramp(3, {}).lookup_alpha({0.3f, 0.3f}), 1.0f);
}

TEST(TextureWrapModes, TexelCentresOutsideTheImageMapAsEachModeDefines) {
    constexpr int n = 4;
    // Texel index i -> the texel each mode reads there (worked out by hand).
    struct Case {
        int i, repeat, clamp, mirror;
    };
    const Case cases[] = {{-5, 3, 0, 3}, {-2, 2, 0, 1}, {-1, 3, 0, 0}, {0, 0, 0, 0},
                          {3, 3, 3, 3},  {4, 0, 3, 3},  {5, 1, 3, 2},  {7, 3, 3, 0},
                          {8, 0, 3, 0},  {9, 1, 3, 1},  {13, 1, 3, 2}};
    for (const TextureFilter f : {TextureFilter::Linear, TextureFilter::Nearest}) {
        const ImageTexture repeat = ramp(n, {TextureWrap::Repeat, TextureWrap::Repeat, f});
        const ImageTexture clamp = ramp(n, {TextureWrap::ClampToEdge, TextureWrap::ClampToEdge, f});
        const ImageTexture mirror =
            ramp(n, {TextureWrap::MirroredRepeat, TextureWrap::MirroredRepeat, f});
        for (const Case& c : cases) {
            const glm::vec2 uv(centre(c.i, n), 0.5f);
            EXPECT_EQ(repeat.lookup(uv).x, float(c.repeat)) << c.i << " filter " << int(f);
            EXPECT_EQ(clamp.lookup(uv).x, float(c.clamp)) << c.i << " filter " << int(f);
            EXPECT_EQ(mirror.lookup(uv).x, float(c.mirror)) << c.i << " filter " << int(f);
        }
    }
}

TEST(TextureWrapModes, VerticalAxisWrapsByItsOwnMode) {
    // 1 x 4, rows top to bottom 0..3: v = 1 is the top (OBJ convention).
    ImageTexture t(1, 4, {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}});
    t.set_sampling({TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureFilter::Linear});
    EXPECT_EQ(t.lookup({0.5f, 1.0f - centre(0, 4)}).x, 0.0f);
    EXPECT_EQ(t.lookup({0.5f, 1.0f - centre(-3, 4)}).x, 0.0f);  // above the top: clamped
    EXPECT_EQ(t.lookup({0.5f, 1.0f - centre(6, 4)}).x, 3.0f);   // below the bottom
    t.set_sampling({TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat, TextureFilter::Linear});
    EXPECT_EQ(t.lookup({0.5f, 1.0f - centre(5, 4)}).x, 2.0f);
    EXPECT_EQ(t.lookup({0.5f, 1.0f - centre(-2, 4)}).x, 1.0f);
}

TEST(TextureFiltering, BilinearWeightsAreTheDistancesToTheTexelCentres) {
    const ImageTexture t = ramp(4, {TextureWrap::ClampToEdge, TextureWrap::Repeat});
    // A quarter of the way from texel 1's centre to texel 2's: 0.75 * 1 + 0.25 * 2.
    EXPECT_EQ(t.lookup({(1.5f + 0.25f) / 4.0f, 0.5f}).x, 1.25f);
    // Half way between 2 and 3.
    EXPECT_EQ(t.lookup({3.0f / 4.0f, 0.5f}).x, 2.5f);
    // Clamp: left of texel 0's centre stays at texel 0; repeat blends 3 and 0 there.
    EXPECT_EQ(t.lookup({0.0f, 0.5f}).x, 0.0f);
    const ImageTexture r = ramp(4, {});
    EXPECT_EQ(r.lookup({0.0f, 0.5f}).x, 1.5f);  // 0.5 * 3 + 0.5 * 0

    // Two dimensions: 2 x 2 with corner values a b / c d; at the point a quarter texel
    // right and down of a's centre, weights (1 - 1/4)(1 - 1/4), ... exactly.
    const float a = 1.0f, b = 2.0f, c = 4.0f, d = 8.0f;
    ImageTexture q(2, 2, {{a, 0, 0}, {b, 0, 0}, {c, 0, 0}, {d, 0, 0}});
    q.set_sampling({TextureWrap::ClampToEdge, TextureWrap::ClampToEdge});
    const float wx = 0.25f, wy = 0.25f;
    const float expected =
        (1 - wy) * ((1 - wx) * a + wx * b) + wy * ((1 - wx) * c + wx * d);  // 2.3125
    // Texel (0, 0)'s centre is u = 0.25, v = 0.75 (top row); a quarter texel = 1/8.
    EXPECT_EQ(q.lookup({0.25f + 0.125f, 0.75f - 0.125f}).x, expected);
}

TEST(TextureFiltering, NearestReadsTheTexelContainingThePoint) {
    const ImageTexture t =
        ramp(4, {TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest});
    EXPECT_EQ(t.lookup({0.01f, 0.5f}).x, 0.0f);
    EXPECT_EQ(t.lookup({0.49f, 0.5f}).x, 1.0f);
    EXPECT_EQ(t.lookup({0.51f, 0.5f}).x, 2.0f);
    EXPECT_EQ(t.lookup({0.99f, 0.5f}).x, 3.0f);
}

TEST(TextureTransformMap, MatchesTheGltfMatrixThenTheVerticalFlip) {
    // KHR_texture_transform worked by hand: scale (2, 3), rotation pi/2, offset (0.1, 0.2).
    // (1, 0) -> S (2, 0) -> R (2 cos, -2 sin) = (0, -2) -> T (0.1, -1.8).
    TextureTransform t;
    t.offset = {0.1f, 0.2f};
    t.rotation = float(M_PI / 2);
    t.scale = {2.0f, 3.0f};
    const glm::mat3x2 m = make_texture_transform(t, false);
    const glm::vec2 p = m * glm::vec3(1.0f, 0.0f, 1.0f);
    EXPECT_NEAR(p.x, 0.1f, 1e-6f);
    EXPECT_NEAR(p.y, -1.8f, 1e-6f);
    // (0, 1) -> S (0, 3) -> R (3 sin, 3 cos) = (3, 0) -> T (3.1, 0.2).
    const glm::vec2 q = m * glm::vec3(0.0f, 1.0f, 1.0f);
    EXPECT_NEAR(q.x, 3.1f, 1e-6f);
    EXPECT_NEAR(q.y, 0.2f, 1e-6f);
    // With glTF uvs, v is flipped after the transform.
    const glm::vec2 f = make_texture_transform(t, true) * glm::vec3(1.0f, 0.0f, 1.0f);
    EXPECT_NEAR(f.x, 0.1f, 1e-6f);
    EXPECT_NEAR(f.y, 2.8f, 1e-6f);
    // The identity without a transform (OBJ uvs), and the same map as the glTF loader's
    // GltfTextureTransform::matrix() for arbitrary parameters.
    const glm::mat3x2 id = make_texture_transform({}, false);
    EXPECT_EQ(id * glm::vec3(0.3f, 0.7f, 1.0f), glm::vec2(0.3f, 0.7f));
    GltfTextureTransform g;
    g.offset = {-0.4f, 0.9f};
    g.rotation = 0.7f;
    g.scale = {1.5f, -0.5f};
    const glm::mat3x2 mine = make_texture_transform({g.offset, g.rotation, g.scale}, false);
    for (const glm::vec2 uv : {glm::vec2(0.2f, 0.3f), glm::vec2(-1.0f, 2.0f)}) {
        const glm::vec3 ref = g.matrix() * glm::vec3(uv, 1.0f);
        const glm::vec2 got = mine * glm::vec3(uv, 1.0f);
        EXPECT_NEAR(got.x, ref.x, 1e-6f);
        EXPECT_NEAR(got.y, ref.y, 1e-6f);
    }
}

}  // namespace
}  // namespace librt

namespace librt {
namespace {

// Issue 42 item 4: 8-bit texels stay 8 bits (4 bytes a texel, not 12 or 16 as floats), and
// every lookup (bilinear and nearest, each wrap mode, colour and alpha) gives the very bits
// of the same texture decoded to floats up front, as textures were stored before.
TEST(TextureMemory, EightBitTexelsStayEightBitAndLookUpTheSameBits) {
    const int w = 7, h = 5;
    std::vector<std::uint8_t> rgba;
    std::uint32_t state = 12345u;
    for (int i = 0; i < 4 * w * h; ++i) {
        state = state * 1664525u + 1013904223u;  // a fixed LCG: any bytes will do
        rgba.push_back(std::uint8_t(state >> 24));
    }
    for (ColorSpace space : {ColorSpace::Srgb, ColorSpace::Linear}) {
        const ImageTexture eight = ImageTexture::from_rgba8(w, h, rgba, space);
        ASSERT_TRUE(eight.eight_bit());
        EXPECT_EQ(eight.texel_bytes(), std::size_t(4 * w * h));
        ASSERT_TRUE(eight.has_alpha());
        std::vector<glm::vec3> floats;
        for (int y = 0; y < h; ++y) {
            for (int x = 0; x < w; ++x) floats.push_back(eight.texel(x, y));
        }
        ImageTexture decoded(w, h, floats);
        EXPECT_EQ(decoded.texel_bytes(), std::size_t(w * h) * sizeof(glm::vec3));
        for (int x = 0; x < w; ++x) {
            const double want =
                space == ColorSpace::Srgb ? srgb_reference(rgba[4 * x]) : rgba[4 * x] / 255.0;
            EXPECT_NEAR(eight.texel(x, 0).x, want, 1e-6 * (1.0 + want));
        }
        for (TextureFilter filter : {TextureFilter::Linear, TextureFilter::Nearest}) {
            for (TextureWrap wrap :
                 {TextureWrap::Repeat, TextureWrap::ClampToEdge, TextureWrap::MirroredRepeat}) {
                ImageTexture a = eight, b = decoded;
                a.set_sampling({wrap, wrap, filter});
                b.set_sampling({wrap, wrap, filter});
                for (int k = 0; k < 200; ++k) {
                    const glm::vec2 uv(-1.3f + 0.0193f * float(k), 2.1f - 0.0271f * float(k));
                    ASSERT_EQ(a.lookup(uv), b.lookup(uv)) << k;
                }
            }
        }
        // Alpha: a/255, filtered as colour is.
        ImageTexture nearest = eight;
        nearest.set_sampling({TextureWrap::Repeat, TextureWrap::Repeat, TextureFilter::Nearest});
        EXPECT_EQ(nearest.lookup_alpha({centre(2, w), 1.0f - centre(0, h)}),
                  float(rgba[4 * 2 + 3]) / 255.0f);
    }
    // Opaque texels: no alpha channel.
    std::vector<std::uint8_t> opaque(4 * 4, 255);
    EXPECT_FALSE(ImageTexture::from_rgba8(2, 2, opaque, ColorSpace::Srgb).has_alpha());
}

}  // namespace
}  // namespace librt
