// The AOV-guided denoiser (render/denoiser.h): what it must leave alone (a constant or a
// noise-free image), determinism across thread counts, its errors, and on a rendered box
// with a checker floor and thin bars: the error reduction, unbiased block means and kept
// edge contrast against a long reference.
#include "box_scene_test_util.h"

#include <librt/core/error.h>
#include <librt/film/film.h>
#include <librt/integrator/integrators.h>
#include <librt/io/image_io.h>
#include <librt/light/quad_light.h>
#include <librt/light/sphere_light.h>
#include <librt/material/texture.h>
#include <librt/render/denoiser.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace librt {
namespace {

/// A width x height input whose layers are all `beauty` (no noise: both halves equal),
/// with the given albedo and normal layers.
DenoiserInput noise_free(const Image& beauty, const Image& albedo, const Image& normal) {
    DenoiserInput in;
    in.beauty = in.half_a = in.half_b = beauty;
    in.albedo = albedo;
    in.normal = normal;
    return in;
}

Image filled(int w, int h, glm::vec3 v) {
    Image im(w, h);
    for (glm::vec3& p : im.pixels) p = v;
    return im;
}

/// An albedo checker of 5-pixel squares (0.2 / 0.8) and normals turning with x.
void textured_features(int w, int h, Image& albedo, Image& normal) {
    albedo = Image(w, h);
    normal = Image(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            albedo.at(x, y) = ((x / 5 + y / 5) % 2 == 0) ? glm::vec3(0.2f, 0.3f, 0.4f)
                                                         : glm::vec3(0.8f, 0.7f, 0.6f);
            const float a = 0.02f * float(x);
            normal.at(x, y) = {std::sin(a), 0.0f, std::cos(a)};
        }
    }
}

TEST(Denoiser, ConstantImageStaysConstant) {
    // Constant radiance over a textured albedo and turning normals: the demodulated values
    // differ from pixel to pixel, the output must not.
    Image albedo, normal;
    textured_features(40, 30, albedo, normal);
    const glm::vec3 c(0.25f, 0.5f, 1.5f);
    const Image out = denoise(noise_free(filled(40, 30, c), albedo, normal));
    for (const glm::vec3& p : out.pixels) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(p[k], c[k], 1e-6f * c[k]);
    }
}

TEST(Denoiser, NoiseFreeImageIsReturnedUnchanged) {
    // Smooth gradients, a hard edge and texture, with zero variance (equal halves): every
    // neighbour whose patch differs at all gets weight 0.
    const int w = 48, h = 36;
    Image albedo, normal;
    textured_features(w, h, albedo, normal);
    Image beauty(w, h);
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const float shade = 0.3f + 0.6f * float(x) / float(w) + (y > h / 2 ? 2.0f : 0.0f);
            beauty.at(x, y) = albedo.at(x, y) * shade;
        }
    }
    const Image out = denoise(noise_free(beauty, albedo, normal));
    for (std::size_t i = 0; i < out.pixels.size(); ++i) {
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.pixels[i][k], beauty.pixels[i][k], 1e-4f);
    }
}

/// Independent noisy halves around `mean`: Gaussian-ish (sum of 4 uniforms) of std
/// `sigma` times the mean.
DenoiserInput noisy_halves(const Image& mean, const Image& albedo, const Image& normal, float sigma,
                           std::uint64_t seed) {
    DenoiserInput in;
    in.albedo = albedo;
    in.normal = normal;
    in.half_a = in.half_b = in.beauty = mean;
    Pcg32 rng(seed, 1);
    const auto noise = [&] {
        float s = 0.0f;
        for (int k = 0; k < 4; ++k) s += rng.next_float() - 0.5f;
        return s * std::sqrt(3.0f);  // unit variance
    };
    for (std::size_t i = 0; i < mean.pixels.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            in.half_a.pixels[i][k] = mean.pixels[i][k] * (1.0f + sigma * noise());
            in.half_b.pixels[i][k] = mean.pixels[i][k] * (1.0f + sigma * noise());
        }
        in.beauty.pixels[i] = 0.5f * (in.half_a.pixels[i] + in.half_b.pixels[i]);
    }
    return in;
}

// Converged bright pixels (a delta light's highlight: its halves agree) among dim, noisy
// pixels and fireflies two pixels away (a glossy surface's rare paths; a half far from the
// other). The fireflies' noise, smoothed over the variance box, lets the plain filter take
// the highlight in with its dim neighbours; with the bound each converged pixel stays
// within max_standard_errors of its box's median standard error, the fireflies are still
// taken down (their own spread frees them), and the dim pixels are still smoothed.
TEST(Denoiser, ConvergedHighlightsKeepTheirValue) {
    const int w = 48, h = 48;
    const Image albedo = filled(w, h, glm::vec3(0.5f));
    Image normal = filled(w, h, glm::vec3(0.0f, 0.0f, 1.0f));
    DenoiserInput in = noisy_halves(filled(w, h, glm::vec3(0.5f)), albedo, normal, 0.3f, 11);
    const int bright[][2] = {{10, 10}, {11, 11}, {12, 12}, {30, 20}, {31, 20}, {20, 35}};
    for (const auto& b : bright) {
        const std::size_t i = std::size_t(b[1]) * std::size_t(w) + std::size_t(b[0]);
        in.half_a.pixels[i] = in.half_b.pixels[i] = in.beauty.pixels[i] = glm::vec3(20.0f);
    }
    std::vector<std::size_t> fireflies;
    for (const auto& b : bright) {
        const std::size_t i = std::size_t(b[1] + 2) * std::size_t(w) + std::size_t(b[0]);
        in.half_b.pixels[i] = in.half_a.pixels[i] + glm::vec3(40.0f);
        in.beauty.pixels[i] = 0.5f * (in.half_a.pixels[i] + in.half_b.pixels[i]);
        fireflies.push_back(i);
    }
    DenoiserSettings unbounded;
    unbounded.max_standard_errors = 0.0f;
    const Image plain = denoise(in, unbounded);
    const Image out = denoise(in);
    // The dim pixels' standard error of the mean: 0.5 x 0.3 / sqrt(2) = 0.106; 3 of them,
    // with the box's median a little below the mean, bound the move well under 0.5.
    float pulled = 0.0f;
    for (const auto& b : bright) {
        const std::size_t i = std::size_t(b[1]) * std::size_t(w) + std::size_t(b[0]);
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.pixels[i][k], 20.0f, 0.5f);
        pulled = std::max(pulled, 20.0f - plain.pixels[i].x);
    }
    // What the bound is for: the plain filter moves some of them by more.
    EXPECT_GT(pulled, 0.5f);
    // A firefly's own halves give it a bound of 3 x 20: it is still taken down.
    for (const std::size_t i : fireflies) EXPECT_LT(out.pixels[i].x, 10.0f) << "pixel " << i;
    double err_in = 0.0, err_out = 0.0;
    // Far from the fireflies (more than the filter's reach, radius 8 plus the patch's 3).
    for (int y = 0; y < 10; ++y)
        for (int x = 36; x < 48; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            err_in += std::pow(in.beauty.pixels[i].x - 0.5, 2.0);
            err_out += std::pow(out.pixels[i].x - 0.5, 2.0);
        }
    EXPECT_LT(err_out * 4.0, err_in);
}

// A highlight converged by many samples (adaptive sampling gave its pixels 64 where the
// first part holds 1), beside dim noisy pixels: a flat-topped disc (an area light's
// reflection) whose edge is a pixel wide. At the edge its halves differ by where in the
// pixel their samples fell, not by noise: the one-sample half is the radiance at a point
// of the pixel filter's footprint (Gaussian, sigma 0.5), the other half what makes the
// beauty exact. That spread is as large as a firefly's (a standard error near 0.5), and a
// bound on it let the filter pull the edge down (textures.glb at 31 spp: 11.1 -> 9.3,
// reference 11.1). Where both halves lie within the range of the pixel's 8 neighbours,
// the bound takes its box's median instead: the disc's interior (converged, halves equal)
// and the background (standard error 0.5 x 0.3 / sqrt(2) = 0.106) hold it to 3 x 0.106
// (0.32), and a little more where the edge's own pixels are most of the 5 x 5 box: 0.5.
TEST(Denoiser, ConvergedHighlightEdgesKeepTheirValue) {
    const int w = 48, h = 48;
    const Image albedo = filled(w, h, glm::vec3(0.5f));
    const Image normal = filled(w, h, glm::vec3(0.0f, 0.0f, 1.0f));
    DenoiserInput in = noisy_halves(filled(w, h, glm::vec3(0.5f)), albedo, normal, 0.3f, 13);
    in.share_a.assign(std::size_t(w) * std::size_t(h), 0.5f);
    const int centres[][2] = {{12, 12}, {32, 18}, {20, 34}};
    const auto radiance = [&](float x, float y) {  // discs of radius 4, 10 brighter
        float v = 0.5f;
        for (const auto& c : centres) {
            const float r = std::hypot(x - float(c[0]), y - float(c[1]));
            v += 10.0f / (1.0f + std::exp((r - 4.0f) / 0.3f));
        }
        return v;
    };
    Pcg32 rng(17, 3);
    const auto footprint = [&] {  // a Gaussian offset of sigma 0.5 (Box-Muller)
        const float u = std::max(rng.next_float(), 1e-7f), v = rng.next_float();
        return 0.5f * std::sqrt(-2.0f * std::log(u)) * std::cos(6.2831853f * v);
    };
    constexpr float kShare = 1.0f / 64.0f;
    std::vector<std::size_t> highlight;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const float v = radiance(float(x), float(y));
            if (v < 1.0f) continue;
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const float a = radiance(float(x) + footprint(), float(y) + footprint());
            in.beauty.pixels[i] = glm::vec3(v);
            in.half_a.pixels[i] = glm::vec3(a);
            in.half_b.pixels[i] = glm::vec3((v - kShare * a) / (1.0f - kShare));
            in.share_a[i] = kShare;
            highlight.push_back(i);
        }
    const Image out = denoise(in);
    for (const std::size_t i : highlight) {
        EXPECT_NEAR(out.pixels[i].x, in.beauty.pixels[i].x, 0.5f)
            << "pixel " << i % w << ", " << i / w;
    }
}

TEST(Denoiser, NoisyConstantImageIsSmoothedWithoutBias) {
    const int w = 64, h = 48;
    Image albedo, normal;
    textured_features(w, h, albedo, normal);
    Image mean(w, h);
    for (std::size_t i = 0; i < mean.pixels.size(); ++i) mean.pixels[i] = albedo.pixels[i];
    const DenoiserInput in = noisy_halves(mean, albedo, normal, 0.3f, 7);
    const Image out = denoise(in);
    double err_in = 0.0, err_out = 0.0, sum_out = 0.0, sum_mean = 0.0;
    for (std::size_t i = 0; i < mean.pixels.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double m = mean.pixels[i][k];
            err_in += std::pow((in.beauty.pixels[i][k] - m) / m, 2.0);
            err_out += std::pow((out.pixels[i][k] - m) / m, 2.0);
            sum_out += out.pixels[i][k];
            sum_mean += m;
        }
    }
    // Noise of relative std 0.3 / sqrt(2) per pixel; averaging ~100 similar neighbours
    // lowers its variance ~100x: 10x is a margin, not a tuning.
    EXPECT_LT(err_out * 10.0, err_in);
    // The image's mean: the noise's standard error is 0.21 / sqrt(3 w h) ~ 0.2 %: 1 %
    // is 5 of them.
    EXPECT_NEAR(sum_out / sum_mean, 1.0, 0.01);
}

/// The mean error of column x of `out` against `truth` over rows [0, h), and its standard
/// error from the spread of the means of bands of `band` rows (bands farther apart than
/// the filter's radius are independent: their noise and their neighbours differ).
struct ColumnError {
    double mean = 0.0;
    double standard_error = 0.0;
};
ColumnError column_error(const Image& out, const Image& truth, int x, int band) {
    std::vector<double> bands;
    for (int y0 = 0; y0 + band <= out.height; y0 += band) {
        double s = 0.0;
        for (int y = y0; y < y0 + band; ++y) s += double(out.at(x, y).y - truth.at(x, y).y);
        bands.push_back(s / band);
    }
    ColumnError e;
    for (const double b : bands) e.mean += b / double(bands.size());
    double var = 0.0;
    for (const double b : bands) var += (b - e.mean) * (b - e.mean) / double(bands.size() - 1);
    e.standard_error = std::sqrt(var / double(bands.size()));
    return e;
}

TEST(Denoiser, LinearGradientUnderNoiseHasNoEdgeBias) {
    // Radiance rising linearly across a flat, one-colour surface (light falling off along a
    // wall), under noise of relative std 0.1 per half, in a tall image: the first and the
    // last columns have neighbours on one side only. A weighted mean pulls them toward the
    // inside by a fraction of the slope times the radius; the first-order fit is unbiased
    // there. Tolerance: 4 standard errors of the column's mean error, from the spread of
    // its means over independent bands of rows (32 rows, the radius is 8).
    const int w = 32, h = 1024;
    Image mean(w, h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) mean.at(x, y) = glm::vec3(1.0f + 0.015f * float(x));
    const DenoiserInput in = noisy_halves(mean, filled(w, h, glm::vec3(0.5f)),
                                          filled(w, h, {0.0f, 0.0f, 1.0f}), 0.1f, 21);
    DenoiserSettings zero;
    zero.first_order = false;
    const Image first = denoise(in);
    const Image plain = denoise(in, zero);
    for (const int x : {0, w - 1}) {
        const ColumnError e = column_error(first, mean, x, 32);
        EXPECT_NEAR(e.mean, 0.0, 4.0 * e.standard_error) << "column " << x;
        // The noise it is measured against: the weighted mean's bias exceeds it there
        // (else the test could not tell the two apart).
        const ColumnError p = column_error(plain, mean, x, 32);
        EXPECT_GT(std::abs(p.mean), 4.0 * p.standard_error + 4.0 * e.standard_error)
            << "column " << x;
    }
    // And the noise is removed: the error's mean square falls 4x or more.
    double err_in = 0.0, err_out = 0.0;
    for (std::size_t i = 0; i < mean.pixels.size(); ++i) {
        err_in += std::pow(double(in.beauty.pixels[i].y - mean.pixels[i].y), 2.0);
        err_out += std::pow(double(first.pixels[i].y - mean.pixels[i].y), 2.0);
    }
    EXPECT_LT(err_out * 4.0, err_in);
}

TEST(Denoiser, ResultScalesWithTheImage) {
    // Units must not matter: a scene in radiometric watts under a 3-lux sun has values near
    // 1e-3 (dragons_instanced.glb), where a fixed epsilon in the patch distance was a tenth
    // of the noise's variance. denoise(c x) = c denoise(x) to float rounding.
    const int w = 40, h = 30;
    Image albedo, normal;
    textured_features(w, h, albedo, normal);
    const DenoiserInput in = noisy_halves(albedo, albedo, normal, 0.3f, 11);
    const float c = 1e-3f;
    DenoiserInput scaled = in;
    for (Image* im : {&scaled.beauty, &scaled.half_a, &scaled.half_b})
        for (glm::vec3& p : im->pixels) p *= c;
    const Image one = denoise(in);
    const Image small = denoise(scaled);
    for (std::size_t i = 0; i < one.pixels.size(); ++i) {
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(small.pixels[i][k], c * one.pixels[i][k], 1e-4f * c * one.pixels[i][k]);
    }
}

TEST(Denoiser, SameBitsForAnyThreadCount) {
    const int w = 75, h = 41;  // not a multiple of the tile side
    Image albedo, normal;
    textured_features(w, h, albedo, normal);
    const DenoiserInput in = noisy_halves(albedo, albedo, normal, 0.5f, 3);
    DenoiserSettings s;
    s.threads = 1;
    const Image one = denoise(in, s);
    for (const int threads : {2, 7}) {
        s.threads = threads;
        const Image many = denoise(in, s);
        ASSERT_EQ(many.pixels.size(), one.pixels.size());
        EXPECT_EQ(std::memcmp(many.pixels.data(), one.pixels.data(),
                              one.pixels.size() * sizeof(glm::vec3)),
                  0)
            << threads << " threads";
    }
}

TEST(Denoiser, BadInputAndSettingsNameWhatIsWrong) {
    Image albedo, normal;
    textured_features(8, 6, albedo, normal);
    DenoiserInput in = noise_free(filled(8, 6, glm::vec3(1.0f)), albedo, normal);
    const auto message = [](const auto& f) {
        try {
            f();
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("(no error)");
    };
    DenoiserInput small = in;
    small.albedo = Image(4, 6);
    EXPECT_NE(message([&] { (void)denoise(small); }).find("albedo is 4 x 6"), std::string::npos);
    DenoiserInput nan = in;
    nan.half_b.at(3, 2).y = std::nanf("");
    EXPECT_NE(message([&] { (void)denoise(nan); }).find("half_b pixel (3, 2) is not finite"),
              std::string::npos);
    DenoiserInput share = in;
    share.share_a.assign(48, 0.5f);
    share.share_a[5] = 1.0f;
    EXPECT_NE(message([&] { (void)denoise(share); }).find("share_a[5] = 1"), std::string::npos);
    DenoiserSettings s;
    s.radius = 0;
    EXPECT_NE(message([&] { (void)denoise(in, s); }).find("radius = 0"), std::string::npos);
    s = {};
    s.normal_sigma = -1.0f;
    EXPECT_NE(message([&] { (void)denoise(in, s); }).find("normal_sigma"), std::string::npos);
    s = {};
    s.max_standard_errors = std::nanf("");
    EXPECT_NE(message([&] { (void)denoise(in, s); }).find("max_standard_errors = nan"),
              std::string::npos);
    // Films: the full one needs AOVs and more samples than the first in every pixel.
    Film first(4, 4, true), full(4, 4, true);
    for (FilmPixel& p : first.pixels) p.samples = p.finite = 2;
    for (FilmPixel& p : full.pixels) p.samples = p.finite = 4;
    full.at(1, 2).samples = 2;
    EXPECT_NE(message([&] { (void)denoiser_input(first, full); }).find("pixel (1, 2)"),
              std::string::npos);
    EXPECT_NE(message([&] { (void)denoiser_input(first, Film(4, 4)); }).find("no AOVs"),
              std::string::npos);
    EXPECT_NE(message([&] { (void)denoiser_input(first, Film(5, 4, true)); }).find("5 x 4"),
              std::string::npos);
}

// --- A rendered scene ---------------------------------------------------------------

constexpr int kSize = 64;

/// The open box with a checker floor (0.1 / 0.8 in 4 x 4 squares) and three thin dark
/// bars (albedo 0.03, about 3 pixels wide) standing before the white back wall.
void build_checker_box(Scene& scene) {
    // Linear bytes 26 and 204: albedos 0.102 and 0.8; nearest texel, so the squares'
    // edges are sharp.
    std::vector<std::uint8_t> rgba(4 * 4 * 4, 255);
    for (int y = 0; y < 4; ++y)
        for (int x = 0; x < 4; ++x)
            for (int c = 0; c < 3; ++c)
                rgba[std::size_t((y * 4 + x) * 4 + c)] = (x + y) % 2 ? 204 : 26;
    TextureSampling nearest;
    nearest.filter = TextureFilter::Nearest;
    const std::int32_t checker =
        scene.add_texture(ImageTexture::from_rgba8(4, 4, rgba, ColorSpace::Linear, nearest));
    Material floor = Material::diffuse(glm::vec3(0.8f));
    floor.albedo_texture = checker;
    TriangleMesh m;
    m.positions = {{-1, 0, -1}, {-1, 0, 1}, {1, 0, 1}, {1, 0, -1}};
    m.uvs = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    m.triangles = {{0, 1, 2}, {0, 2, 3}};
    scene.add_mesh(m, scene.add_material(floor));
    const auto dark = scene.add_material(Material::diffuse(glm::vec3(0.03f)));
    for (const float x : {-0.5f, 0.0f, 0.5f})
        testing::add_quad(scene, {x - 0.075f, 0.3f, -0.9f}, {0.15f, 0, 0}, {0, 1.4f, 0}, dark);
    // The walls of testing::build_box (its floor is the checker here) and its quad light.
    const auto white = scene.add_material(Material::diffuse(glm::vec3(0.73f)));
    const auto red = scene.add_material(Material::diffuse({0.65f, 0.05f, 0.05f}));
    const auto green = scene.add_material(Material::diffuse({0.12f, 0.45f, 0.15f}));
    testing::add_quad(scene, {-1, 2, -1}, {0, 0, 2}, {2, 0, 0}, white);  // ceiling
    testing::add_quad(scene, {-1, 0, -1}, {0, 2, 0}, {2, 0, 0}, white);  // back
    testing::add_quad(scene, {-1, 0, -1}, {0, 0, 2}, {0, 2, 0}, red);    // left
    testing::add_quad(scene, {1, 0, -1}, {0, 2, 0}, {0, 0, 2}, green);   // right
    (void)scene.add_quad_light(
        QuadLight{{-0.25f, 1.99f, -0.25f}, {0.5f, 0, 0}, {0, 0, 0.5f}, glm::vec3(10.0f), false});
    scene.commit();
}

struct Rendered {
    Film half;  // samples [0, spp / 2)
    Film full;  // samples [0, spp)
};

Rendered render_box(const Scene& scene, int spp, std::uint64_t seed) {
    // box_camera_settings, looking down by 6.7 degrees: the floor fills more of the view,
    // and the ceiling's light, whose edges only a long render resolves, is out of it.
    CameraSettings cs = testing::box_camera_settings(kSize);
    cs.look_at = {0.0f, 0.6f, 0.0f};
    const Camera camera(cs);
    PathTracer pt;
    pt.preprocess(scene);
    BlockSettings rs;
    rs.seed = seed;
    rs.sampler = SamplerKind::Independent;  // the halves differ by independent noise
    Rendered r;
    r.full = Film(kSize, kSize, true);
    (void)render_block(scene, camera, pt, r.full, {0, 0, kSize, kSize, 0, std::uint32_t(spp / 2)},
                       rs);
    r.half = r.full;
    (void)render_block(scene, camera, pt, r.full,
                       {0, 0, kSize, kSize, std::uint32_t(spp / 2), std::uint32_t(spp - spp / 2)},
                       rs);
    return r;
}

/// relMSE: mean of (x - ref)^2 / (ref^2 + 0.01) over pixels and channels.
double rel_mse(const Image& x, const Image& ref) {
    double s = 0.0;
    for (std::size_t i = 0; i < x.pixels.size(); ++i) {
        for (int k = 0; k < 3; ++k) {
            const double d = double(x.pixels[i][k]) - double(ref.pixels[i][k]);
            s += d * d / (double(ref.pixels[i][k]) * ref.pixels[i][k] + 0.01);
        }
    }
    return s / double(3 * x.pixels.size());
}

float luminance(glm::vec3 c) { return 0.2126f * c.x + 0.7152f * c.y + 0.0722f * c.z; }

class DenoisedBox : public ::testing::Test {
protected:
    static void SetUpTestSuite() {
        scene_ = new Scene;
        build_checker_box(*scene_);
        // The reference: 2048 samples per pixel with another seed (its own noise is
        // ~1/128 of the 16-sample image's variance; it only makes the checks harder).
        reference_ = new ImageLayers(resolve_layers(render_box(*scene_, 2048, 99).full));
        const Rendered noisy = render_box(*scene_, 16, 1);
        input_ = new DenoiserInput(denoiser_input(noisy.half, noisy.full));
        denoised_ = new Image(denoise(*input_));
        if (const char* dump = std::getenv("DENOISER_TEST_DUMP")) {
            write_image(std::string(dump) + "_noisy.pfm", input_->beauty);
            write_image(std::string(dump) + "_denoised.pfm", *denoised_);
            write_image(std::string(dump) + "_ref.pfm", reference_->beauty);
            write_image(std::string(dump) + "_albedo.pfm", reference_->albedo);
            write_image(std::string(dump) + "_ha.pfm", input_->half_a);
            write_image(std::string(dump) + "_hb.pfm", input_->half_b);
            write_image(std::string(dump) + "_aa.pfm", input_->albedo_a);
            write_image(std::string(dump) + "_ab.pfm", input_->albedo_b);
        }
    }
    static void TearDownTestSuite() {
        delete denoised_;
        delete input_;
        delete reference_;
        delete scene_;
    }

    /// Mean luminance of the pixels whose reference albedo (luminance) is in [lo, hi],
    /// within rows [y0, y1).
    static double class_mean(const Image& image, float lo, float hi, int y0, int y1) {
        double s = 0.0;
        int n = 0;
        for (int y = y0; y < y1; ++y) {
            for (int x = 0; x < kSize; ++x) {
                const float a = luminance(reference_->albedo.at(x, y));
                if (a >= lo && a <= hi) {
                    s += luminance(image.at(x, y));
                    ++n;
                }
            }
        }
        EXPECT_GT(n, 10) << "rows " << y0 << ".." << y1 << " albedo " << lo << ".." << hi;
        return s / std::max(n, 1);
    }

    static Scene* scene_;
    static ImageLayers* reference_;
    static DenoiserInput* input_;
    static Image* denoised_;
};
Scene* DenoisedBox::scene_ = nullptr;
ImageLayers* DenoisedBox::reference_ = nullptr;
DenoiserInput* DenoisedBox::input_ = nullptr;
Image* DenoisedBox::denoised_ = nullptr;

TEST_F(DenoisedBox, ErrorLowerAt16Samples) {
    // This scene is mostly edges at 64 x 64 (checker squares a few pixels tall, bars 3
    // pixels wide), where a pixel's coverage is noise no neighbour shares: 3.1x measured.
    // The 4x target is asserted on the plain box below.
    const double noisy = rel_mse(input_->beauty, reference_->beauty);
    const double denoised = rel_mse(*denoised_, reference_->beauty);
    EXPECT_GT(noisy, 2.0 * denoised) << "relMSE noisy " << noisy << ", denoised " << denoised;
}

TEST(DenoiserFilms, PassDoneSeesEveryLevelAndTheHalfFilmDenoises) {
    // rt_render's way to the half buffers: render_progressive's pass_done gets the film
    // after every pass, holding that pass's level in every pixel; the copy at half the
    // samples and the final film make the denoiser's input.
    Scene scene;
    testing::build_box(scene, false, false, false);
    CameraSettings cs = testing::box_camera_settings(16);
    const Camera camera(cs);
    PathTracer pt;
    ProgressiveSettings ps;
    ps.render.samples_per_pixel = 4;
    ps.render.adaptive.enabled = false;  // every pixel the pass's level (adaptive: the pilot's)
    ps.aovs = true;
    std::vector<std::uint32_t> levels;
    Film half;
    ps.pass_done = [&](const Film& f, std::uint32_t level) {
        levels.push_back(level);
        EXPECT_EQ(uniform_sample_count(f), level);
        if (level == 2) half = f;
    };
    Film film;
    (void)render_progressive(scene, camera, pt, film, ps);
    EXPECT_EQ(levels, (std::vector<std::uint32_t>{1, 2, 3, 4}));
    const DenoiserInput in = denoiser_input(half, film);
    ASSERT_EQ(in.share_a.size(), 256u);
    EXPECT_EQ(in.share_a[0], 0.5f);
    // The halves put together are the film's mean: b from the difference of the sums.
    for (std::size_t i = 0; i < in.beauty.pixels.size(); ++i) {
        const glm::vec3 mean = 0.5f * (in.half_a.pixels[i] + in.half_b.pixels[i]);
        for (int k = 0; k < 3; ++k)
            EXPECT_NEAR(mean[k], in.beauty.pixels[i][k], 1e-5f * (1.0f + in.beauty.pixels[i][k]));
    }
    const Image out = denoise(in);
    for (const glm::vec3& p : out.pixels) EXPECT_TRUE(std::isfinite(p.x + p.y + p.z));
}

TEST(DenoisedCornellBox, ErrorAtLeastFourTimesLowerAt16Samples) {
    // The tests' open box (testing::build_box) with its glossy metal slab, seen through
    // the same camera; the reference is 2048 samples per pixel with another seed.
    Scene scene;
    testing::build_box(scene, false, false, true);
    const Image reference = resolve(render_box(scene, 2048, 99).full);
    const Rendered noisy = render_box(scene, 16, 1);
    const DenoiserInput in = denoiser_input(noisy.half, noisy.full);
    const double before = rel_mse(in.beauty, reference);
    const double after = rel_mse(denoise(in), reference);
    EXPECT_GT(before, 4.0 * after) << "relMSE noisy " << before << ", denoised " << after;
}

TEST_F(DenoisedBox, BlockMeansKeepTheReferences) {
    // 16 x 16 blocks. The denoiser may move light within a block's neighbourhood only; the
    // noisy block mean's own error, estimated from the halves, is allowed on top of 1 %:
    // Var(block mean) = sum over its pixels of (a - b)^2 / 4, / 256^2 (equal halves).
    for (int by = 0; by < kSize; by += 16) {
        for (int bx = 0; bx < kSize; bx += 16) {
            double den = 0.0, ref = 0.0, var = 0.0;
            for (int y = by; y < by + 16; ++y) {
                for (int x = bx; x < bx + 16; ++x) {
                    den += luminance(denoised_->at(x, y));
                    ref += luminance(reference_->beauty.at(x, y));
                    const double d =
                        luminance(input_->half_a.at(x, y)) - luminance(input_->half_b.at(x, y));
                    var += d * d / 4.0;
                }
            }
            den /= 256.0;
            ref /= 256.0;
            const double sigma = std::sqrt(var) / 256.0;
            EXPECT_NEAR(den, ref, 0.01 * ref + 4.0 * sigma) << "block (" << bx << ", " << by << ")";
        }
    }
}

TEST_F(DenoisedBox, CheckerAndThinBarContrastKept) {
    // Contrast: the mean of the bright class minus that of the dark class, pixels picked
    // by the reference's albedo (pure pixels only, edges' neighbours included: blurring
    // across an edge brightens the dark side and darkens the bright one).
    // Floor rows (the checker) and back-wall rows (the bars against the white wall).
    const auto contrast = [&](const Image& im, float dark_lo, float dark_hi, float bright_lo,
                              float bright_hi, int y0, int y1) {
        return class_mean(im, bright_lo, bright_hi, y0, y1) -
               class_mean(im, dark_lo, dark_hi, y0, y1);
    };
    const double checker_ref = contrast(reference_->beauty, 0.09f, 0.11f, 0.79f, 0.81f, 48, 64);
    const double checker_den = contrast(*denoised_, 0.09f, 0.11f, 0.79f, 0.81f, 48, 64);
    EXPECT_NEAR(checker_den, checker_ref, 0.05 * checker_ref);
    const double bars_ref = contrast(reference_->beauty, 0.0f, 0.035f, 0.72f, 0.74f, 20, 40);
    const double bars_den = contrast(*denoised_, 0.0f, 0.035f, 0.72f, 0.74f, 20, 40);
    EXPECT_NEAR(bars_den, bars_ref, 0.05 * bars_ref);
}

/// Whether every 16 x 16 block of `out` is within 1 % of the reference's block mean plus 4
/// standard errors of the noisy and the reference block means, each from its halves:
/// Var(mean of a pixel) = s (1 - s) (a - b)^2. Returns the brightest reference pixel.
double expect_blocks_kept(const DenoiserInput& in, const Image& out, const DenoiserInput& ref) {
    const auto pixel_var = [](const DenoiserInput& d, std::size_t i) {
        const double s = d.share_a[i];
        const double diff = luminance(d.half_a.pixels[i]) - luminance(d.half_b.pixels[i]);
        return s * (1.0 - s) * diff * diff;
    };
    double brightest = 0.0;
    for (int by = 0; by < kSize; by += 16) {
        for (int bx = 0; bx < kSize; bx += 16) {
            double den = 0.0, reference = 0.0, var = 0.0;
            for (int y = by; y < by + 16; ++y) {
                for (int x = bx; x < bx + 16; ++x) {
                    const std::size_t i = std::size_t(y) * kSize + std::size_t(x);
                    den += luminance(out.pixels[i]);
                    reference += luminance(ref.beauty.pixels[i]);
                    var += pixel_var(in, i) + pixel_var(ref, i);
                    brightest = std::max(brightest, double(luminance(ref.beauty.pixels[i])));
                }
            }
            EXPECT_NEAR(den / 256.0, reference / 256.0,
                        0.01 * reference / 256.0 + 4.0 * std::sqrt(var) / 256.0)
                << "block (" << bx << ", " << by << ")";
        }
    }
    return brightest;
}

TEST(DenoisedBrightFeature, BlockMeansKeepTheReference) {
    // The open box with a small sphere light in view (radius 0.1, about 5 pixels across,
    // radiance 40: 60 times the walls), lit by the ceiling's quad light as well. Its edge
    // pixels mix the emitter (albedo 0) with the wall, and their noise (the share of their
    // samples on the sphere) lets them take in any neighbour: remodulated by an average of
    // radiance / albedo, the emitter's pixels came back multiplied by the edge's albedo
    // over 0.02, edge pixels of 150-214, and the blocks around it +37 % and +44 %
    // (docs/benchmarks.md). Every 16 x 16 block's mean must stay within 1 %
    // of the reference's plus 4 standard errors of the noisy and the reference block
    // means, each from its halves: Var(mean of a pixel) = s (1 - s) (a - b)^2.
    Scene scene;
    testing::build_box(scene, false, false, false);  // the walls and the quad light
    // Near the corner of four blocks (pixel (32, 32) is the image's centre, where the
    // camera looks: (0, 0.6, 0)), so that light pulled out of its own block lands in the
    // others'.
    (void)scene.add_sphere_light(
        SphereLight{Sphere{{0.12f, 0.52f, -0.3f}, 0.1f}, glm::vec3(40.0f)});
    scene.commit();
    const Rendered ref_films = render_box(scene, 2048, 99);
    const DenoiserInput ref = denoiser_input(ref_films.half, ref_films.full);
    const Rendered noisy = render_box(scene, 16, 1);
    const DenoiserInput in = denoiser_input(noisy.half, noisy.full);
    const Image out = denoise(in);
    if (const char* dump = std::getenv("DENOISER_TEST_DUMP")) {
        write_image(std::string(dump) + "_bright_noisy.pfm", in.beauty);
        write_image(std::string(dump) + "_bright_denoised.pfm", out);
        write_image(std::string(dump) + "_bright_ref.pfm", ref.beauty);
    }
    const double brightest = expect_blocks_kept(in, out, ref);
    // The feature is in the image and is bright: its pixels reach 60 times the walls'.
    EXPECT_GT(brightest, 20.0);
}

TEST(DenoisedEmitterEdge, BlockMeansKeepTheReference) {
    // An emissive panel facing the camera on the back wall (about 12 x 8 pixels, radiance
    // 15: some 50 times the wall), as cornell_pbr.glb's panel: its edge pixels mix the
    // emitter with the wall. The emission layers hold what the first hits emit, and the
    // denoiser filters them apart from the light reflected. Every block within 1 % plus 4
    // standard errors. (This scene passes without the emission layers too: the -7.6 % of
    // cornell_pbr.glb's panel block is not reproduced at 64 x 64.)
    Scene scene;
    testing::build_box(scene, false, false, false);
    // Across the image's centre (pixel (32, 32)), so that its edges cross four blocks.
    // An emissive mesh with a dark reflective base, as glTF's emissive panels are (base
    // colour black, a dielectric's specular: albedo about 0.04, not the 0 of a pure emitter).
    Material glow = Material::diffuse(glm::vec3(0.04f));
    glow.emission = glm::vec3(15.0f);
    testing::add_quad(scene, {-0.2f, 0.3f, -0.98f}, {0.6f, 0, 0}, {0, 0.4f, 0},
                      scene.add_material(glow));
    scene.commit();
    const Rendered ref_films = render_box(scene, 2048, 99);
    const DenoiserInput ref = denoiser_input(ref_films.half, ref_films.full);
    const Rendered noisy = render_box(scene, 16, 1);
    const DenoiserInput in = denoiser_input(noisy.half, noisy.full);
    // The emission layers: the panel's radiance where a pixel sees only it, 0 on the walls.
    EXPECT_EQ(in.emission_a.at(32, 32), glm::vec3(15.0f));
    EXPECT_EQ(in.emission_b.at(32, 32), glm::vec3(15.0f));
    EXPECT_EQ(in.emission_a.at(4, 32), glm::vec3(0.0f));
    const Image out = denoise(in);
    if (const char* dump = std::getenv("DENOISER_TEST_DUMP")) {
        write_image(std::string(dump) + "_panel_noisy.pfm", in.beauty);
        write_image(std::string(dump) + "_panel_denoised.pfm", out);
        write_image(std::string(dump) + "_panel_ref.pfm", ref.beauty);
    }
    EXPECT_GT(expect_blocks_kept(in, out, ref), 10.0);  // the panel is in view
}

}  // namespace
}  // namespace librt
