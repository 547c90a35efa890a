// The AOV-guided denoiser (denoiser.h): cross-filtered half buffers, demodulated by the
// albedo, averaged by non-local means with feature weights.

#include <librt/core/error.h>
#include <librt/render/denoiser.h>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <mutex>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

namespace librt {

namespace {

/// The guides (what the patch distances compare) divide the radiance by max(albedo, this),
/// per channel: a miss (albedo 0: the sky, an emitter seen directly) or a black surface is
/// compared in units of this instead of being divided by 0. Such pixels are kept apart
/// from lit surfaces by the features.
constexpr float kMinAlbedo = 0.02f;

/// The albedo below which the output is not demodulated (see PixelTerms): where a pixel
/// mixes an emitter (albedo 0) with a lit surface, e.g. the edge of a small light, the
/// emitter's radiance is not albedo x light, and a small albedo in the ratio multiplied it
/// back up to 5x the emitter's own radiance (DenoisedBrightFeature; docs/benchmarks.md).
/// 0.05 still did so in that test; 0.1 and 0.2 did not.
constexpr float kModulationFloor = 0.1f;

/// Rousselle et al.'s epsilon, relative to the image's mean square (demodulated): the
/// patch distance's denominator where the noise is 0, so that a noise-free image keeps
/// every difference (any difference above ~1e-5 of the image's RMS gives a weight of
/// exp(-1)). Relative, so that the filter does not depend on the units (a scene lit in
/// radiometric watts by a 3-lux sun has values near 1e-3): denoise(c x) = c denoise(x).
constexpr float kRelativeEpsilon = 1e-12f;

/// The noise estimate (a - b)^2 of one pixel has one degree of freedom: averaged over a
/// (2 x 2 + 1)^2 box it is usable. Larger boxes blur the estimate across edges.
constexpr int kVarianceRadius = 2;
/// The box whose median standard error bounds a pixel's move (bound_by_own_noise): 5 x 5,
/// measured against 3 x 3 (the same figures within 1 %) on cornell_pbr.glb and
/// material_spheres.glb.
constexpr int kBoundRadius = 2;
/// The neighbours whose noisy values a pixel's halves are compared with in
/// bound_by_own_noise: 3 x 3, the reach of rt_render's pixel filter (a Gaussian of sigma
/// 0.5 cut at 1.5 pixels). A half within their range may differ from the other by where
/// in the pixel its samples fell (a highlight's edge crossing the pixel), not by noise:
/// the halves' spread then measures that part too, which the pixel's other samples
/// average out (Sobol' points stratify the pixel: textures.glb's highlight at 31 spp was
/// within 0.5 % of its reference while its own standard error said 8 %), so the pixel
/// gets its box's median. A half beyond that range (a firefly, a caustic speck) is noise
/// no neighbour shows, and the pixel's own spread frees it.
constexpr int kFootprintRadius = 1;
/// ... only where one half holds at most this share of the pixel's samples (adaptive
/// sampling's first part: 1/8 of a pixel's samples or less where the sampler sent more).
/// A part of a few samples cannot stratify the pixel, so where in it they fell dominates
/// its difference at an edge; halves of equal size are each stratified, and their
/// difference is noise: with the rule for them too, librt_denoise_figures' renders (equal
/// halves) lost 10-15 % of their gain, the synthesis at 64 spp 60.5x -> 5.8x.
constexpr float kFewSamplesShare = 0.25f;

/// Rows of the strips threads take: the rows of a strip share the patch-distance buffers
/// of each neighbour offset (and their apron of 2 x patch radius rows, which the next strip
/// computes again: 6 rows more per 32 rather than per 16; the same bits either way: the
/// patch sums are exact, Quantum).
constexpr int kStrip = 32;

/// The albedo's prefilter: a smaller neighbourhood (the albedo's noise is only at edges,
/// where neighbours along the edge are near) and Rousselle et al. 2013's k = 1 for their
/// feature prefilter.
constexpr int kPrefilterRadius = 5;
constexpr float kPrefilterStrength = 1.0f;

/// The widest vector the filter's loops use (AVX2: 8 floats). The rows of patch distances
/// are computed to a multiple of it, so that no row ends in a scalar remainder (callgrind:
/// 6 % of the filter's instructions were the remainders of 70-pixel rows); the planes
/// carry this many floats more, which those extra lanes may read past the last row.
constexpr int kLanes = 8;

/// exp(-x) for x >= 0 (the callers' x is a sum of terms >= 0; NaN gives 0), branch-free so
/// the loops over a row vectorise: 2^(-x log2 e) split into an integer power (built in the
/// exponent bits) and a fraction (a degree-4 polynomial, relative error below 4e-6, far
/// below what the weights need). 0 beyond x = 80. The same bits on every machine: plain
/// float arithmetic, no libm.
[[gnu::always_inline]] inline float exp_neg(float x) {
    // One min (minps returns its second operand for a NaN); a test for x < 0 as well cost
    // 9 instructions per vector the way g++ compiled the two together.
    x = x < 80.0f ? x : 80.0f;
    const float t = x * 1.44269504f;  // -log2 of the result
    // t >= 0: truncation is floor, and SSE2 converts by truncation (std::floor would be a
    // library call without SSE4.1, which stops the loop's vectorisation).
    const float whole = static_cast<float>(static_cast<std::int32_t>(t));
    const float f = whole - t;  // in (-1, 0]: the result is 2^f x 2^-whole
    // 2^f on [-1, 0]: the polynomial through its values at the 5 Chebyshev nodes of the
    // interval (near-minimax; the degree-6 Taylor series of e^(f ln 2) used before erred
    // by up to 2.8e-5 at f = -1, with 3 more multiplications).
    const float p =
        0.99999804f +
        f * (0.693048934f + f * (0.239430604f + f * (0.0532131178f + f * 0.00683515473f)));
    const auto exponent = static_cast<std::int32_t>(127.0f - whole);  // >= 11: a normal float
    return p * std::bit_cast<float>(exponent << 23);
}

void check_layer(const Image& layer, const Image& beauty, const char* name) {
    if (layer.width != beauty.width || layer.height != beauty.height) {
        throw Error(std::string("denoise: layer ") + name + " is " + std::to_string(layer.width) +
                    " x " + std::to_string(layer.height) + ", the beauty " +
                    std::to_string(beauty.width) + " x " + std::to_string(beauty.height));
    }
    for (std::size_t i = 0; i < layer.pixels.size(); ++i) {
        const glm::vec3& v = layer.pixels[i];
        if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) {
            const auto w = static_cast<std::size_t>(layer.width);
            throw Error(std::string("denoise: layer ") + name + " pixel (" + std::to_string(i % w) +
                        ", " + std::to_string(i / w) + ") is not finite");
        }
    }
}

void check_input(const DenoiserInput& in) {
    check_layer(in.beauty, in.beauty, "beauty");
    check_layer(in.albedo, in.beauty, "albedo");
    check_layer(in.normal, in.beauty, "normal");
    check_layer(in.half_a, in.beauty, "half_a");
    check_layer(in.half_b, in.beauty, "half_b");
    const auto optional_pair = [&](const Image& x, const Image& y, const char* nx, const char* ny) {
        if (x.pixels.empty() && y.pixels.empty() && x.width == 0 && y.width == 0) return;
        check_layer(x, in.beauty, nx);
        check_layer(y, in.beauty, ny);
    };
    optional_pair(in.albedo_a, in.albedo_b, "albedo_a", "albedo_b");
    optional_pair(in.normal_a, in.normal_b, "normal_a", "normal_b");
    optional_pair(in.emission_a, in.emission_b, "emission_a", "emission_b");
    if (!in.share_a.empty()) {
        if (in.share_a.size() != in.beauty.pixels.size()) {
            throw Error("denoise: share_a has " + std::to_string(in.share_a.size()) +
                        " values, the beauty " + std::to_string(in.beauty.pixels.size()) +
                        " pixels");
        }
        for (std::size_t i = 0; i < in.share_a.size(); ++i) {
            if (!(in.share_a[i] > 0.0f && in.share_a[i] < 1.0f)) {
                throw Error("denoise: share_a[" + std::to_string(i) +
                            "] = " + std::to_string(in.share_a[i]) + ": must be in (0, 1)");
            }
        }
    }
}

/// Mean of `v` over the (2r + 1)^2 box around each pixel, clipped to the image.
std::vector<glm::vec3> box_mean(const std::vector<glm::vec3>& v, int width, int height, int r) {
    std::vector<glm::vec3> rows(v.size()), out(v.size());
    for (int y = 0; y < height; ++y) {
        for (int x = 0; x < width; ++x) {
            glm::vec3 s(0.0f);
            const int x0 = std::max(0, x - r), x1 = std::min(width - 1, x + r);
            for (int i = x0; i <= x1; ++i) s += v[std::size_t(y) * std::size_t(width) + i];
            rows[std::size_t(y) * std::size_t(width) + x] = s / float(x1 - x0 + 1);
        }
    }
    for (int y = 0; y < height; ++y) {
        const int y0 = std::max(0, y - r), y1 = std::min(height - 1, y + r);
        for (int x = 0; x < width; ++x) {
            glm::vec3 s(0.0f);
            for (int j = y0; j <= y1; ++j) s += rows[std::size_t(j) * std::size_t(width) + x];
            out[std::size_t(y) * std::size_t(width) + x] = s / float(y1 - y0 + 1);
        }
    }
    return out;
}

/// The planes the filter reads, one float per pixel and channel (structure of arrays, so
/// that the loops over a row vectorise), padded by `pad` pixels on every side with copies
/// of the nearest edge pixel: a neighbour's patch may reach past the image.
struct Planes {
    int width = 0;                   ///< the image's
    int height = 0;                  ///< the image's
    int pad = 0;                     ///< radius + patch radius
    int stride = 0;                  ///< width + 2 pad
    float epsilon = 0.0f;            ///< kRelativeEpsilon x the mean square of a and b
    std::vector<float> a[3];         ///< half_a demodulated
    std::vector<float> b[3];         ///< half_b demodulated
    std::vector<float> value_a[3];   ///< what is averaged of a: its radiance (PixelTerms)
    std::vector<float> value_b[3];   ///< the same of b
    std::vector<float> albedo_a[3];  ///< a's albedo (floored), averaged with the same weights
    std::vector<float> albedo_b[3];  ///< the same of b
    /// value_a / albedo_a: what the first-order filter fits (the demodulated radiance)
    std::vector<float> ratio_a[3];
    std::vector<float> ratio_b[3];  ///< the same of b
    std::vector<float> var_a[3];    ///< noise variance of a (smoothed)
    std::vector<float> var_b[3];    ///< noise variance of b (smoothed)
    std::vector<float> albedo[3];   ///< the albedo AOV
    std::vector<float> normal[3];   ///< the normal AOV
    std::vector<float> albedo_var;  ///< noise variance of the albedo, summed over channels
    std::vector<float> normal_var;  ///< noise variance of the normal, summed over components
    /// sigma^2 plus the albedo's largest squared difference to its 4 neighbours: at an edge
    /// of the albedo (a texture, an object's outline) the feature is not trusted to tell
    /// neighbours apart, and the radiance's patch distance decides (Rousselle, Manzi &
    /// Zwicker 2013 bound the feature distance by the feature's gradient the same way).
    std::vector<float> albedo_tol;
    std::vector<float> normal_tol;  ///< the same for the normal

    /// Whether what is averaged (value_a, value_b) is 0 in padded rows [y0, y1): then so is
    /// the filter's output of the rows whose neighbourhoods lie within (sum of w x 0).
    [[nodiscard]] bool zero_rows(int y0, int y1) const {
        const std::size_t from = at(-pad, y0), to = at(-pad, y1);
        for (int c = 0; c < 3; ++c) {
            for (std::size_t i = from; i < to; ++i)
                if (value_a[c][i] != 0.0f || value_b[c][i] != 0.0f) return false;
        }
        return true;
    }

    /// Index of image pixel (x, y), which may lie in the padding.
    [[nodiscard]] std::size_t at(int x, int y) const {
        return std::size_t(y + pad) * std::size_t(stride) + std::size_t(x + pad);
    }
};

/// What the output needs per image pixel: the modulation and the shares. A half's output
/// at p is m_p x (sum of w_q L_q) / (sum of w_q m_q): the neighbours' radiance, averaged,
/// over their albedo averaged with the same weights, times p's albedo (a ratio of
/// averages). Where the albedo is one colour it is the plain average of the radiance; over
/// a texture under even light (L_q = E m_q) it is E m_p exactly, as an average of the
/// ratios L_q / m_q would be; but a neighbour of small albedo is not multiplied by m_p /
/// m_q on its own, so a bright emitter (albedo 0) beside a pixel of some albedo is not
/// made brighter than it is.
struct PixelTerms {
    std::vector<glm::vec3> modulation;  ///< m_p: max(the prefiltered albedo, kModulationFloor)
    std::vector<float> share;           ///< share_a per pixel
    /// What the first hits emit, filtered on its own (denoise), added to the output; empty
    /// for none.
    std::vector<glm::vec3> emission;
};

/// The first-order filter's two estimates of each half's demodulated radiance per pixel:
/// the weighted mean and the fit's intercept; select_estimates keeps one.
struct Estimates {
    std::vector<glm::vec3> mean_a, mean_b, fit_a, fit_b;
};

/// The planes of `in`, with `albedo` in place of in.albedo (the prefiltered albedo) as the
/// feature and what the result is multiplied back by.
Planes make_planes(const DenoiserInput& in, const Image& albedo, const DenoiserSettings& settings,
                   PixelTerms& terms) {
    const int w = in.beauty.width, h = in.beauty.height;
    const std::size_t n = in.beauty.pixels.size();
    terms.modulation.resize(n);
    terms.share = in.share_a.empty() ? std::vector<float>(n, 0.5f) : in.share_a;
    const bool albedo_halves = !in.albedo_a.pixels.empty();
    const Image& albedo_a = albedo_halves ? in.albedo_a : albedo;
    const Image& albedo_b = albedo_halves ? in.albedo_b : albedo;
    const bool normal_halves = !in.normal_a.pixels.empty();
    const bool emission = !in.emission_a.pixels.empty();
    // The light reflected: each half less what its first hits emit (DenoiserInput::emission_a).
    std::vector<glm::vec3> ra = in.half_a.pixels, rb = in.half_b.pixels;
    if (emission) {
        for (std::size_t i = 0; i < n; ++i) {
            ra[i] -= in.emission_a.pixels[i];
            rb[i] -= in.emission_b.pixels[i];
        }
    }
    std::vector<glm::vec3> da(n), db(n), spread(n), feature_spread(n);
    for (std::size_t i = 0; i < n; ++i) {
        terms.modulation[i] = glm::max(albedo.pixels[i], glm::vec3(kModulationFloor));
        // Each half by its own albedo (DenoiserInput::albedo_a); the result is multiplied
        // back by the albedo of all the samples.
        da[i] = ra[i] / glm::max(albedo_a.pixels[i], glm::vec3(kMinAlbedo));
        db[i] = rb[i] / glm::max(albedo_b.pixels[i], glm::vec3(kMinAlbedo));
        const glm::vec3 d = da[i] - db[i];
        spread[i] = d * d;
        // The AOVs' own noise (a texture or a silhouette inside the pixel, partly hit): as
        // for the radiance below, Var(all samples' mean) = s (1 - s) E[(a - b)^2].
        const glm::vec3 fa = albedo_a.pixels[i] - albedo_b.pixels[i];
        const glm::vec3 fn =
            normal_halves ? in.normal_a.pixels[i] - in.normal_b.pixels[i] : glm::vec3(0.0f);
        const float s = terms.share[i];
        feature_spread[i] = glm::vec3(glm::dot(fa, fa), glm::dot(fn, fn), 0.0f) * (s * (1.0f - s));
    }
    // With a share s of the samples in a: Var(a) = sigma^2 / (s n), Var(b) = sigma^2 /
    // ((1 - s) n), and E[(a - b)^2] = Var(a) + Var(b); so Var(a) = (1 - s) E[(a - b)^2].
    const std::vector<glm::vec3> smooth = box_mean(spread, w, h, kVarianceRadius);
    const std::vector<glm::vec3> feature_var = box_mean(feature_spread, w, h, kVarianceRadius);
    std::vector<glm::vec3> va(n), vb(n), fv_albedo(n), fv_normal(n);
    for (std::size_t i = 0; i < n; ++i) {
        va[i] = smooth[i] * (1.0f - terms.share[i]);
        vb[i] = smooth[i] * terms.share[i];
        fv_albedo[i] = glm::vec3(feature_var[i].x);
        fv_normal[i] = glm::vec3(feature_var[i].y);
    }
    std::vector<glm::vec3> tol_albedo(n), tol_normal(n);
    const float sa2 = settings.albedo_sigma * settings.albedo_sigma;
    const float sn2 = settings.normal_sigma * settings.normal_sigma;
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            float ga = 0.0f, gn = 0.0f;
            const int nx[4] = {x - 1, x + 1, x, x};
            const int ny[4] = {y, y, y - 1, y + 1};
            for (int k = 0; k < 4; ++k) {
                if (nx[k] < 0 || nx[k] >= w || ny[k] < 0 || ny[k] >= h) continue;
                const std::size_t j = std::size_t(ny[k]) * std::size_t(w) + std::size_t(nx[k]);
                const glm::vec3 ea = albedo.pixels[i] - albedo.pixels[j];
                const glm::vec3 en = in.normal.pixels[i] - in.normal.pixels[j];
                ga = std::max(ga, glm::dot(ea, ea));
                gn = std::max(gn, glm::dot(en, en));
            }
            tol_albedo[i] = glm::vec3(sa2 + ga);
            tol_normal[i] = glm::vec3(sn2 + gn);
        }
    }
    Planes p;
    p.width = w;
    p.height = h;
    p.pad = settings.radius + settings.patch_radius;
    p.stride = w + 2 * p.pad;
    double square = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        square += double(glm::dot(da[i], da[i])) + double(glm::dot(db[i], db[i]));
    // At least 1e-30 (a normal float), so that an all-zero image divides by > 0.
    p.epsilon = std::max(kRelativeEpsilon * float(square / double(6 * std::max<std::size_t>(n, 1))),
                         1e-30f);
    const std::size_t padded = std::size_t(p.stride) * std::size_t(h + 2 * p.pad);
    const auto fill = [&](std::vector<float>* plane, const std::vector<glm::vec3>& from) {
        for (int c = 0; c < 3; ++c) {
            plane[c].resize(padded + std::size_t(kLanes));  // kLanes: distances' extra lanes
            for (int y = -p.pad; y < h + p.pad; ++y) {
                const int cy = std::min(std::max(y, 0), h - 1);
                const glm::vec3* src = &from[std::size_t(cy) * std::size_t(w)];
                float* row = &plane[c][p.at(0, y)];  // row[x], x in [-pad, w + pad)
                for (int x = -p.pad; x < 0; ++x) row[x] = src[0][c];
                for (int x = 0; x < w; ++x) row[x] = src[x][c];
                for (int x = w; x < w + p.pad; ++x) row[x] = src[w - 1][c];
            }
        }
    };
    fill(p.a, da);
    fill(p.b, db);
    fill(p.value_a, ra);
    fill(p.value_b, rb);
    std::vector<glm::vec3> ma(n), mb(n);
    for (std::size_t i = 0; i < n; ++i) {
        ma[i] = glm::max(albedo_a.pixels[i], glm::vec3(kModulationFloor));
        mb[i] = glm::max(albedo_b.pixels[i], glm::vec3(kModulationFloor));
    }
    fill(p.albedo_a, ma);
    fill(p.albedo_b, mb);
    std::vector<glm::vec3> ya(n), yb(n);
    for (std::size_t i = 0; i < n; ++i) {
        ya[i] = ra[i] / ma[i];
        yb[i] = rb[i] / mb[i];
    }
    fill(p.ratio_a, ya);
    fill(p.ratio_b, yb);
    fill(p.var_a, va);
    fill(p.var_b, vb);
    fill(p.albedo, albedo.pixels);
    fill(p.normal, in.normal.pixels);
    std::vector<float> one[3];
    fill(one, fv_albedo);
    p.albedo_var = std::move(one[0]);
    fill(one, fv_normal);
    p.normal_var = std::move(one[0]);
    fill(one, tol_albedo);
    p.albedo_tol = std::move(one[0]);
    fill(one, tol_normal);
    p.normal_tol = std::move(one[0]);
    return p;
}

/// The filter's loops are plain float arithmetic over rows, which g++ vectorises: with AVX2
/// (8 lanes) where the CPU has it, else SSE2 (4), chosen when the library loads (an ifunc).
/// The same bits either way: the build contracts no multiply-add (-ffp-contract=off) and
/// the AVX2 target enables no FMA, so each lane does the same IEEE operations.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define LIBRT_DENOISE_CLONES __attribute__((target_clones("avx2", "default")))
#define LIBRT_DENOISE_INLINE [[gnu::always_inline]]
/// Before a loop whose stores overlap none of its loads: g++ checks the pointers at run time
/// for at most 10 pairs and leaves a loop with more (the weights' loop reads 16 planes) scalar.
#define LIBRT_DENOISE_NO_ALIAS _Pragma("GCC ivdep")
#else
#define LIBRT_DENOISE_CLONES
#define LIBRT_DENOISE_INLINE
#define LIBRT_DENOISE_NO_ALIAS
#endif

/// The first-order regression's design (Moon et al. 2014, "Adaptive rendering based on
/// weighted local regression"; Bitterli et al. 2016, NFOR): per pixel p and half, the
/// demodulated radiance of the neighbours q is fitted as a + b . (q - p) / radius by least
/// squares with the non-local-means weights, and a, the fit at p, is the output: a
/// gradient across the neighbourhood (a ceiling brightening toward a light, seen from one
/// side at the image's edge) no longer pulls p toward the side with more neighbours. The
/// normal difference as three more features (light from one direction is linear in the
/// normal) was measured and not kept: with a ridge of 0.1 the same figures within 1-6 %
/// on every scene (docs/benchmarks.md), for 2.6 times the sums.
constexpr int kDesign = 3;  ///< 1, dx, dy
/// The Gram matrix's upper triangle and the right-hand sides (3 channels), per half.
constexpr int kGram = kDesign * (kDesign + 1) / 2;
constexpr int kRegressionSums = kGram + 3 * kDesign;
/// The sums of one row of offsets (one dy) that the regression sums are made of
/// (StripFilter::regress): w, w dx, w dx^2, and w y, w y dx per channel.
constexpr int kPartialSums = 3 + 2 * 3;
/// Ridge regularisation, relative to the weights' sum, added to each slope's diagonal
/// entry: where the neighbours do not span the offsets (one pixel holding all the weight)
/// the slope goes to 0 and the fit to the weighted mean. Small, because a ridge shrinks
/// the slope and brings the mean's bias back at an edge (LinearGradientUnderNoise: 0.1 and
/// 0.01 failed it); the variance a small ridge leaves is select_estimates' to weigh.
constexpr double kRidge = 0.001;
/// The box over which select_estimates averages the two estimates' errors: 9 x 9.
constexpr int kSelectRadius = 4;
/// The least weight of a pixel in its own fit (StripFilter::add_centre).
constexpr float kMinCentreWeight = 1e-6f;

/// Columns of the tiles threads take (with kStrip rows): the sums of a tile (up to
/// 2 (kRegressionSums + kPartialSums) + 2 planes, 400 KB) stay in the core's cache while
/// every neighbour offset is added to them.
constexpr int kTileWidth = 64;
/// Pixels of a tile's plane of sums.
constexpr std::size_t kTilePixels = std::size_t(kStrip) * std::size_t(kTileWidth);

/// n rounded up to a multiple of kLanes.
constexpr int round_to_lanes(int n) { return (n + kLanes - 1) / kLanes * kLanes; }

/// The per-pixel patch distances as integers, so that the patch box can be a running sum
/// (over y: one row in, one out per row) that is exact in any order: a float running sum
/// would carry the rounding of every distance that passed through it, and a far neighbour's
/// distance is many orders above a near one's. Each distance is clamped to [low, high] and
/// multiplied by `scale` (truncated): low = -3 / k^2 is the least a distance can be (per
/// channel -(Var p + min) / (k^2 (Var p + Var q)) >= -1 / k^2), and high is where one pixel
/// alone, the others at low, puts the patch beyond exp_neg's 80, so the clamp changes no
/// weight. scale is the largest with n x high x scale <= 2^30 (n pixels in a patch): no
/// sum overflows. The truncation moves a patch's exponent by less than n / (3 n scale)
/// = 1 / (3 scale): below 2e-4 at the default settings (scale ~1757).
struct Quantum {
    float low = 0.0f;
    float high = 0.0f;
    float scale = 1.0f;
    float unit = 1.0f;  ///< patch sum -> exponent: 1 / (scale x 3 n)
    Quantum() = default;
    explicit Quantum(const DenoiserSettings& s) {
        const int side = 2 * s.patch_radius + 1;
        const double n = double(side) * double(side);
        const double k2 = double(s.strength) * double(s.strength);
        low = float(-3.0 / k2);
        const double top = 240.0 * n + (n - 1.0) * 3.0 / k2;  // 80 x 3n + (n - 1) |low|
        high = float(top);
        scale = float(double(1 << 30) / (n * top));
        unit = float(1.0 / (double(scale) * 3.0 * n));
    }
};

/// Filters tiles [x0, x1) x [y0, y1); each thread has one.
class StripFilter {
public:
    StripFilter(const Planes& planes, const DenoiserSettings& s, bool first_order)
        : p_(planes), s_(s), first_order_(first_order) {
        const int f = s.patch_radius;
        const std::size_t rows = std::size_t(kStrip + 2 * f);
        const std::size_t width = std::size_t(round_to_lanes(kTileWidth + 2 * f));
        dist_a_.resize(rows * width);
        dist_b_.resize(dist_a_.size());
        // kLanes more, kept 0: the box over x of the last vector reads up to kLanes - 1
        // values past a row's end.
        column_a_.resize(width + std::size_t(kLanes));
        column_b_.resize(column_a_.size());
        quantum_ = Quantum(s);
        // First order: each half's regression sums, each half's largest weight, each half's
        // partial sums (regress).
        sums_.resize(kTilePixels *
                     std::size_t(first_order ? 2 * kRegressionSums + 2 + 2 * kPartialSums : 12));
        for (std::vector<float>* v : {&patch_a_, &patch_b_}) v->resize(std::size_t(kTileWidth));
    }

    LIBRT_DENOISE_CLONES void run(int x0t, int x1t, int y0, int y1, const PixelTerms& terms,
                                  Estimates& estimates, Image& out) {
        const int f = s_.patch_radius, r = s_.radius, w = p_.width;
        const int tw = x1t - x0t;
        // A distance row: x in [x0t - f, x1t + f), and more, read only by the boxes of
        // lanes past the tile.
        const int dw = round_to_lanes(round_to_lanes(tw) + 2 * f);
        std::fill(sums_.begin(), sums_.end(), 0.0f);
        const float k2 = s_.strength * s_.strength;
        // Neighbour offsets in a fixed order: each output pixel sums its neighbours in this
        // order whatever thread or tile computes it.
        for (int oy = -r; oy <= r; ++oy) {
            for (int ox = -r; ox <= r; ++ox) {
                // The first-order fit takes the pixel itself last (add_centre).
                if (first_order_ && ox == 0 && oy == 0) continue;
                const int x0 = std::max(x0t, -ox), x1 = std::min(x1t, w - ox);
                if (x1 <= x0) continue;
                // 1. Per-pixel distances d(p, p + o) over the tile and its apron, for the
                //    guide of each half: the other half (cross-filtering), as integers.
                {
                    const std::size_t p0 = p_.at(x0t - f, y0 - f);
                    const std::size_t q0 = p_.at(x0t - f + ox, y0 - f + oy);
                    const int rows = y1 - y0 + 2 * f;
                    const auto stride = std::size_t(p_.stride);
                    distances(p_.b, p_.var_b, p0, q0, rows, stride, dw, k2, p_.epsilon, quantum_,
                              dist_a_.data());  // filters a
                    distances(p_.a, p_.var_a, p0, q0, rows, stride, dw, k2, p_.epsilon, quantum_,
                              dist_b_.data());  // filters b
                }
                // 2. The patch box: over y a running sum per column (one row in, one out),
                //    over x direct sums of those (accumulate); exact in integers, so every
                //    pixel gets the same sums wherever its tile lies. 3. Weights and
                //    accumulation, for neighbours in the image.
                for (int j = 0; j < y1 - y0; ++j) {
                    const auto row = [&](const std::vector<std::int32_t>& d, int k) {
                        return &d[std::size_t(k) * std::size_t(dw)];
                    };
                    if (j == 0) {
                        column_start(row(dist_a_, 0), std::size_t(dw), 2 * f + 1, dw,
                                     column_a_.data());
                        column_start(row(dist_b_, 0), std::size_t(dw), 2 * f + 1, dw,
                                     column_b_.data());
                    } else {
                        column_step(row(dist_a_, j + 2 * f), row(dist_a_, j - 1), dw,
                                    column_a_.data());
                        column_step(row(dist_b_, j + 2 * f), row(dist_b_, j - 1), dw,
                                    column_b_.data());
                    }
                    const int y = y0 + j;
                    if (y + oy < 0 || y + oy >= p_.height) continue;
                    const std::size_t pp = p_.at(0, y), qq = p_.at(ox, y + oy);
                    accumulate(std::size_t(j), tw, x0t, pp, qq, x0, x1, f, float(ox) / float(r));
                }
            }
            if (first_order_)
                fold_partial_sums(std::size_t(y1 - y0) * std::size_t(tw), float(oy) / float(r));
        }
        if (first_order_) add_centre(x0t, x1t, y0, y1);
        for (int y = y0; y < y1; ++y) {
            for (int x = x0t; x < x1t; ++x) {
                const std::size_t t = std::size_t(y - y0) * std::size_t(tw) + std::size_t(x - x0t);
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                if (first_order_) {
                    estimates.fit_a[i] = solve(0, t, estimates.mean_a[i]);
                    estimates.fit_b[i] = solve(1, t, estimates.mean_b[i]);
                    continue;
                }
                const glm::vec3 fa = ratio(0, t);
                const glm::vec3 fb = ratio(1, t);
                const float sh = terms.share[i];
                out.pixels[i] = terms.modulation[i] * (sh * fa + (1.0f - sh) * fb);
                if (!terms.emission.empty()) out.pixels[i] += terms.emission[i];
            }
        }
    }

private:
    /// The pixel itself in its own fit, with the largest of its neighbours' weights
    /// (Buades et al. 2005's choice for non-local means) instead of its self-similarity 1:
    /// a pixel one of whose halves caught a rare bright path (a firefly) finds no patch like
    /// its own, and with weight 1 against neighbours of 0.1 it kept its value
    /// (dragons_instanced.glb's worst pixels). At least kMinCentreWeight: where no
    /// neighbour is alike (a noise-free image's unique detail) the pixel is its own.
    void add_centre(int x0t, int x1t, int y0, int y1) {
        const int tw = x1t - x0t;
        for (int h = 0; h < 2; ++h) {
            const int base = h * kRegressionSums;
            const float* top = sum(2 * kRegressionSums + h);
            for (int y = y0; y < y1; ++y) {
                const std::size_t row = std::size_t(y - y0) * std::size_t(tw);
                const std::size_t q0 = p_.at(x0t, y);
                for (int x = 0; x < tw; ++x) {
                    const float c = std::max(top[row + std::size_t(x)], kMinCentreWeight);
                    sum(base)[row + std::size_t(x)] += c;
                    for (int ch = 0; ch < 3; ++ch)
                        sum(base + kGram + ch)[row + std::size_t(x)] +=
                            c * (h == 0 ? p_.ratio_a : p_.ratio_b)[ch][q0 + std::size_t(x)];
                }
            }
        }
    }

    /// Plane k of the sums (zero order: half h's sums of w L in 6 h + c, of w m in
    /// 6 h + 3 + c; first order: half h's regression sums from h kRegressionSums).
    [[nodiscard]] float* sum(int k) { return &sums_[std::size_t(k) * kTilePixels]; }

    /// The zero-order output of half h at tile pixel t: the neighbours' radiance over
    /// their albedo, both averaged with the weights (PixelTerms). The pixel itself always
    /// weighs 1 (its distance to itself is <= 0 and its features are its own): the
    /// weights never sum to 0.
    [[nodiscard]] glm::vec3 ratio(int h, std::size_t t) {
        glm::vec3 v;
        for (int c = 0; c < 3; ++c) v[c] = sum(6 * h + c)[t] / sum(6 * h + 3 + c)[t];
        return v;
    }

    /// The first-order output of half h at tile pixel t: the intercept of the weighted,
    /// ridge-regularised least squares fit (kDesign), by Cholesky in double precision, and
    /// in `mean` the weighted mean. The weighted mean where the fit is degenerate.
    [[nodiscard]] glm::vec3 solve(int h, std::size_t t, glm::vec3& mean) {
        const int base = h * kRegressionSums;
        double g[kDesign][kDesign];
        int k = 0;
        for (int i = 0; i < kDesign; ++i)
            for (int j = i; j < kDesign; ++j) g[i][j] = g[j][i] = double(sum(base + k++)[t]);
        double rhs[3][kDesign];
        for (int c = 0; c < 3; ++c)
            for (int i = 0; i < kDesign; ++i) rhs[c][i] = double(sum(base + kGram + 3 * i + c)[t]);
        const double w = g[0][0];
        mean = glm::vec3(float(rhs[0][0] / w), float(rhs[1][0] / w), float(rhs[2][0] / w));
        for (int i = 1; i < kDesign; ++i) g[i][i] += kRidge * w;
        // Cholesky G = L L^T in place (lower triangle).
        for (int j = 0; j < kDesign; ++j) {
            double d = g[j][j];
            for (int m = 0; m < j; ++m) d -= g[j][m] * g[j][m];
            if (!(d > 1e-12 * w)) return mean;
            g[j][j] = std::sqrt(d);
            for (int i = j + 1; i < kDesign; ++i) {
                double e = g[i][j];
                for (int m = 0; m < j; ++m) e -= g[i][m] * g[j][m];
                g[i][j] = e / g[j][j];
            }
        }
        glm::vec3 v;
        for (int c = 0; c < 3; ++c) {
            double z[kDesign];
            for (int i = 0; i < kDesign; ++i) {
                double e = rhs[c][i];
                for (int m = 0; m < i; ++m) e -= g[i][m] * z[m];
                z[i] = e / g[i][i];
            }
            for (int i = kDesign - 1; i >= 0; --i) {
                double e = z[i];
                for (int m = i + 1; m < kDesign; ++m) e -= g[m][i] * z[m];
                z[i] = e / g[i][i];
            }
            v[c] = float(z[0]);
        }
        return v;
    }

    /// Rousselle et al.'s per-pixel distance, summed over the channels, for `rows` rows of n
    /// pixels (n a multiple of kLanes) from p0 and q0 = p0 + offset, the rows `stride`
    /// apart in the planes and n apart in `out`: the squared difference minus what the
    /// noise alone would give on average (Var p + min(Var p, Var q): a noisier neighbour is
    /// not favoured), in units of k^2 (Var p + Var q), as an integer (Quantum). (Dividing
    /// by k^2 (Var p + min(Var p, Var q)) instead was measured: material_spheres.glb's
    /// relMSE gain at 64 spp fell from 4.3x to 2.6x.) The three channels in one pass; q's
    /// values are read at p's index plus one offset, so that the loop keeps its pointers
    /// in registers.
    LIBRT_DENOISE_INLINE static void distances(const std::vector<float>* u,
                                               const std::vector<float>* v, std::size_t p0,
                                               std::size_t q0, int rows, std::size_t stride, int n,
                                               float k2, float epsilon, const Quantum& quantum,
                                               std::int32_t* out) {
        const float *u0 = &u[0][p0], *u1 = &u[1][p0], *u2 = &u[2][p0];
        const float *v0 = &v[0][p0], *v1 = &v[1][p0], *v2 = &v[2][p0];
        const auto dq = std::ptrdiff_t(q0) - std::ptrdiff_t(p0);
        const float low = quantum.low, high = quantum.high, scale = quantum.scale;
        // One channel's term (spelled out per channel below: a loop over the channels
        // stopped g++'s vectoriser).
        const auto term = [k2, epsilon](float a, float b, float va, float vb) {
            const float diff = a - b;
            const float lower = vb < va ? vb : va;
            return (diff * diff - (va + lower)) / (epsilon + k2 * (va + vb));
        };
        for (int r = 0; r < rows; ++r) {
            const auto o = std::ptrdiff_t(r) * std::ptrdiff_t(stride);
            std::int32_t* row = out + std::ptrdiff_t(r) * std::ptrdiff_t(n);
            LIBRT_DENOISE_NO_ALIAS
            for (std::ptrdiff_t x = o; x < o + n; ++x) {
                const std::ptrdiff_t y = x + dq;
                float d = term(u0[x], u0[y], v0[x], v0[y]);
                d += term(u1[x], u1[y], v1[x], v1[y]);
                d += term(u2[x], u2[y], v2[x], v2[y]);
                // Two steps, each one min or max (nested, g++ compiled 9 instructions).
                const float capped = d < high ? d : high;
                row[x - o] = static_cast<std::int32_t>((capped > low ? capped : low) * scale);
            }
        }
    }

    /// column[x] = sum of the first `terms` rows (`step` apart) of `in` at x, for x in
    /// [0, n): the box over y of a tile's first row.
    LIBRT_DENOISE_INLINE static void column_start(const std::int32_t* in, std::size_t step,
                                                  int terms, int n, std::int32_t* column) {
        for (int x = 0; x < n; ++x) column[x] = in[x];
        for (int t = 1; t < terms; ++t) {
            const std::int32_t* row = in + std::size_t(t) * step;
            for (int x = 0; x < n; ++x) column[x] += row[x];
        }
    }

    /// out[x] = (column[x] + ... + column[x + 2F]) x unit for x in [0, n): the box over x of
    /// the column sums, the patch distance in the exponent's units. F a constant, so that
    /// the terms unroll and the loop over x vectorises (a loop over the terms inside did
    /// not, nor one kLanes-wide block per step).
    template <int F>
    LIBRT_DENOISE_INLINE static void box_x(const std::int32_t* column, int n, float unit,
                                           float* out) {
        for (int x = 0; x < n; ++x) {
            const std::int32_t* c = column + x;  // one pointer: the terms at fixed displacements
            std::int32_t s = c[0];
            for (int t = 1; t <= 2 * F; ++t) s += c[t];
            out[x] = float(s) * unit;
        }
    }

    /// box_x for patch radius f in [0, 8] (validate).
    LIBRT_DENOISE_INLINE static void box_x(int f, const std::int32_t* column, int n, float unit,
                                           float* out) {
        switch (f) {
            case 0:
                box_x<0>(column, n, unit, out);
                break;
            case 1:
                box_x<1>(column, n, unit, out);
                break;
            case 2:
                box_x<2>(column, n, unit, out);
                break;
            case 3:
                box_x<3>(column, n, unit, out);
                break;
            case 4:
                box_x<4>(column, n, unit, out);
                break;
            case 5:
                box_x<5>(column, n, unit, out);
                break;
            case 6:
                box_x<6>(column, n, unit, out);
                break;
            case 7:
                box_x<7>(column, n, unit, out);
                break;
            default:
                box_x<8>(column, n, unit, out);
                break;
        }
    }

    /// The box over y moved down one row: the row entering added, the one leaving taken
    /// out (exact: integers).
    LIBRT_DENOISE_INLINE static void column_step(const std::int32_t* entering,
                                                 const std::int32_t* leaving, int n,
                                                 std::int32_t* column) {
        for (int x = 0; x < n; ++x) column[x] += entering[x] - leaving[x];
    }

    /// Adds the neighbours at offset (ox, oy) (dx: ox scaled) to the sums of tile row j
    /// (image pixels x0 .. x1 of row pp, neighbours from qq on; the tile starts at x0t and
    /// is tw wide), from the column sums of the patch distances (column_a_, column_b_).
    LIBRT_DENOISE_INLINE void accumulate(std::size_t j, int tw, int x0t, std::size_t pp,
                                         std::size_t qq, int x0, int x1, int f, float dx) {
        const auto w = std::size_t(tw);
        const int n = x1 - x0;
        float* ca = patch_a_.data();
        float* cb = patch_b_.data();
        const std::int32_t* col_a = column_a_.data() + (x0 - x0t);
        const std::int32_t* col_b = column_b_.data() + (x0 - x0t);
        const std::size_t p0 = pp + std::size_t(x0), q0 = qq + std::size_t(x0);
        // q's values at p's index plus one offset: the loop keeps its pointers in registers.
        const auto dq = std::ptrdiff_t(q0) - std::ptrdiff_t(p0);
        const float *a0p = &p_.albedo[0][p0], *a1p = &p_.albedo[1][p0], *a2p = &p_.albedo[2][p0];
        const float *n0p = &p_.normal[0][p0], *n1p = &p_.normal[1][p0], *n2p = &p_.normal[2][p0];
        const float* vap = &p_.albedo_var[p0];
        const float* vnp = &p_.normal_var[p0];
        const float* tap = &p_.albedo_tol[p0];
        const float* tnp = &p_.normal_tol[p0];
        // In whole vectors: up to kLanes - 1 weights past ca[n) are computed (the planes and
        // the columns have that slack) and not read.
        const int nv = round_to_lanes(n);
        box_x(f, col_a, nv, quantum_.unit, ca);
        box_x(f, col_b, nv, quantum_.unit, cb);
        // Feature distances: the squared difference, less what the features' own noise
        // explains, over sigma^2 widened by that noise (where a pixel's albedo or normal is
        // itself a noisy mix, an edge inside it, the features cannot tell it apart and the
        // radiance's patch distance decides); with the patch distances, the weights.
        LIBRT_DENOISE_NO_ALIAS
        for (std::ptrdiff_t x = 0; x < nv; ++x) {
            const std::ptrdiff_t q = x + dq;
            const float a0 = a0p[x] - a0p[q], a1 = a1p[x] - a1p[q], a2 = a2p[x] - a2p[q];
            const float n0 = n0p[x] - n0p[q], n1 = n1p[x] - n1p[q], n2 = n2p[x] - n2p[q];
            const float fa = a0 * a0 + a1 * a1 + a2 * a2;
            const float fn = n0 * n0 + n1 * n1 + n2 * n2;
            const float la = vap[q] < vap[x] ? vap[q] : vap[x];
            const float ln = vnp[q] < vnp[x] ? vnp[q] : vnp[x];
            const float ea = fa - (vap[x] + la);
            const float en = fn - (vnp[x] + ln);
            const float feature = (ea > 0.0f ? ea : 0.0f) / (tap[x] + vap[x] + vap[q]) +
                                  (en > 0.0f ? en : 0.0f) / (tnp[x] + vnp[x] + vnp[q]);
            // exp_neg's argument is >= 0: the feature term is, and so is max(patch, 0).
            ca[x] = exp_neg((ca[x] > 0.0f ? ca[x] : 0.0f) + feature);
            cb[x] = exp_neg((cb[x] > 0.0f ? cb[x] : 0.0f) + feature);
        }
        const std::size_t row = j * w + std::size_t(x0 - x0t);
        if (!first_order_) {
            // All twelve sums in one loop (planes kTilePixels apart: one pointer). g++ left
            // it scalar when it checked the pointers for overlap (callgrind: 16 % of the
            // filter's instructions at 240 x 135), and one loop per sum cost a loop's setup
            // per sum and row.
            float* sums = sum(0) + row;
            const float *qa0 = &p_.value_a[0][q0], *qa1 = &p_.value_a[1][q0],
                        *qa2 = &p_.value_a[2][q0];
            const float *qb0 = &p_.value_b[0][q0], *qb1 = &p_.value_b[1][q0],
                        *qb2 = &p_.value_b[2][q0];
            const float *ma0 = &p_.albedo_a[0][q0], *ma1 = &p_.albedo_a[1][q0],
                        *ma2 = &p_.albedo_a[2][q0];
            const float *mb0 = &p_.albedo_b[0][q0], *mb1 = &p_.albedo_b[1][q0],
                        *mb2 = &p_.albedo_b[2][q0];
            const auto at = [sums](int k, int x) -> float& {
                return sums[std::size_t(k) * kTilePixels + std::size_t(x)];
            };
            LIBRT_DENOISE_NO_ALIAS
            for (int x = 0; x < n; ++x) {
                at(0, x) += ca[x] * qa0[x];
                at(1, x) += ca[x] * qa1[x];
                at(2, x) += ca[x] * qa2[x];
                at(3, x) += ca[x] * ma0[x];
                at(4, x) += ca[x] * ma1[x];
                at(5, x) += ca[x] * ma2[x];
                at(6, x) += cb[x] * qb0[x];
                at(7, x) += cb[x] * qb1[x];
                at(8, x) += cb[x] * qb2[x];
                at(9, x) += cb[x] * mb0[x];
                at(10, x) += cb[x] * mb1[x];
                at(11, x) += cb[x] * mb2[x];
            }
            return;
        }
        regress(0, ca, p_.ratio_a, q0, row, n, dx);
        regress(1, cb, p_.ratio_b, q0, row, n, dx);
    }

    /// Half h's partial sums at this offset (w, w dx, w dx^2, w y, w y dx), from which
    /// fold_partial_sums makes the regression sums (the Gram matrix of the design
    /// (1, dx, dy) and its products with the demodulated radiance) once per row of
    /// offsets: dy is constant along the row, so w dy, w dx dy, w dy^2 and w y dy are dy
    /// and dy^2 times those sums (9 sums per offset and half instead of 15). All in one
    /// loop (the planes kTilePixels apart: one pointer).
    LIBRT_DENOISE_INLINE void regress(int h, const float* weight, const std::vector<float>* y,
                                      std::size_t q0, std::size_t row, int n, float dx) {
        float* top = sum(2 * kRegressionSums + h) + row;
        float* sums = sum(2 * kRegressionSums + 2 + h * kPartialSums) + row;
        const auto at = [sums](int k, int x) -> float& {
            return sums[std::size_t(k) * kTilePixels + std::size_t(x)];
        };
        const float dxx = dx * dx;
        const float *y0 = &y[0][q0], *y1 = &y[1][q0], *y2 = &y[2][q0];
        LIBRT_DENOISE_NO_ALIAS
        for (int x = 0; x < n; ++x) {
            const float wx = weight[x];
            top[x] = top[x] > wx ? top[x] : wx;
            at(0, x) += wx;
            at(1, x) += wx * dx;
            at(2, x) += wx * dxx;
            const float v0 = wx * y0[x], v1 = wx * y1[x], v2 = wx * y2[x];
            at(3, x) += v0;
            at(4, x) += v1;
            at(5, x) += v2;
            at(6, x) += v0 * dx;
            at(7, x) += v1 * dx;
            at(8, x) += v2 * dx;
        }
    }

    /// Adds the partial sums of a row of offsets (regress) to the regression sums of the
    /// first `pixels` tile pixels, dy the row's offset, and clears them.
    void fold_partial_sums(std::size_t pixels, float dy) {
        const float dyy = dy * dy;
        for (int h = 0; h < 2; ++h) {
            float* g = sum(h * kRegressionSums);
            float* part = sum(2 * kRegressionSums + 2 + h * kPartialSums);
            const auto at = [](float* plane, int k, std::size_t t) -> float& {
                return plane[std::size_t(k) * kTilePixels + t];
            };
            LIBRT_DENOISE_NO_ALIAS
            for (std::size_t t = 0; t < pixels; ++t) {
                // The Gram matrix's upper triangle row by row: (1, 1) (1, dx) (1, dy)
                // (dx, dx) (dx, dy) (dy, dy); then per channel y, y dx, y dy.
                const float w = at(part, 0, t), wdx = at(part, 1, t);
                at(g, 0, t) += w;
                at(g, 1, t) += wdx;
                at(g, 2, t) += w * dy;
                at(g, 3, t) += at(part, 2, t);
                at(g, 4, t) += wdx * dy;
                at(g, 5, t) += w * dyy;
                for (int c = 0; c < 3; ++c) {
                    const float v = at(part, 3 + c, t);
                    at(g, kGram + c, t) += v;
                    at(g, kGram + 3 + c, t) += at(part, 6 + c, t);
                    at(g, kGram + 6 + c, t) += v * dy;
                }
                for (int k = 0; k < kPartialSums; ++k) at(part, k, t) = 0.0f;
            }
        }
    }

    const Planes& p_;
    const DenoiserSettings& s_;
    bool first_order_ = false;
    Quantum quantum_;
    std::vector<std::int32_t> dist_a_, dist_b_;      ///< per-pixel distances, tile + apron
    std::vector<std::int32_t> column_a_, column_b_;  ///< their box over y, one row
    std::vector<float> sums_;
    std::vector<float> patch_a_, patch_b_;  ///< one row each: accumulate's weights
};

/// Per pixel, the first-order fit or the weighted mean, whichever errs less, and the
/// output from it. The fit has no bias on a slope but more variance where few neighbours
/// weigh (a glossy highlight, fine texture: with a ridge small enough to keep the slope,
/// material_spheres.glb lost 6.3x -> 4.9x at 64 spp); NFOR (Bitterli et al. 2016) selects
/// among its filters the same way. Each estimate of a half is compared with the other
/// half's noisy value, independent of its samples: E[(F_a - y_b)^2] = MSE(F_a) + Var(y_b),
/// the same Var for both estimates; the squared differences of both halves are summed over
/// the channels and averaged over the 9 x 9 box (one pixel's are too noisy to choose by;
/// 5 x 5 gave the same figures within 4 % and left the gradient test's edge biased).
void select_estimates(const Planes& planes, const PixelTerms& terms, const Estimates& e,
                      Image& out) {
    const int w = planes.width, h = planes.height;
    const std::size_t n = out.pixels.size();
    std::vector<glm::vec3> err(n);  // x: the mean's squared difference, y: the fit's
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
            const std::size_t k = planes.at(x, y);
            const glm::vec3 ya(planes.ratio_a[0][k], planes.ratio_a[1][k], planes.ratio_a[2][k]);
            const glm::vec3 yb(planes.ratio_b[0][k], planes.ratio_b[1][k], planes.ratio_b[2][k]);
            const glm::vec3 dm_a = e.mean_a[i] - yb, dm_b = e.mean_b[i] - ya;
            const glm::vec3 df_a = e.fit_a[i] - yb, df_b = e.fit_b[i] - ya;
            err[i] = glm::vec3(glm::dot(dm_a, dm_a) + glm::dot(dm_b, dm_b),
                               glm::dot(df_a, df_a) + glm::dot(df_b, df_b), 0.0f);
        }
    }
    const std::vector<glm::vec3> smooth = box_mean(err, w, h, kSelectRadius);
    for (std::size_t i = 0; i < n; ++i) {
        const bool fit = smooth[i].y <= smooth[i].x;
        const glm::vec3 fa = fit ? e.fit_a[i] : e.mean_a[i];
        const glm::vec3 fb = fit ? e.fit_b[i] : e.mean_b[i];
        const float sh = terms.share[i];
        out.pixels[i] = terms.modulation[i] * (sh * fa + (1.0f - sh) * fb);
        if (!terms.emission.empty()) out.pixels[i] += terms.emission[i];
    }
}

/// The filter: `in`'s halves demodulated by their albedos, filtered with each other's
/// weights (a first-order regression or, `first_order` false, a weighted mean), multiplied
/// back by `albedo`, plus `emission` (0x0: none).
Image filter_halves(const DenoiserInput& input, const Image& albedo,
                    const DenoiserSettings& settings, const Image& emission, bool first_order) {
    PixelTerms terms;
    const Planes planes = make_planes(input, albedo, settings, terms);
    terms.emission = emission.pixels;
    Image out(planes.width, planes.height);
    Estimates estimates;
    if (first_order) {
        for (std::vector<glm::vec3>* v :
             {&estimates.mean_a, &estimates.mean_b, &estimates.fit_a, &estimates.fit_b})
            v->resize(out.pixels.size());
    }
    const int strips = (planes.height + kStrip - 1) / kStrip;
    const int columns = (planes.width + kTileWidth - 1) / kTileWidth;
    const int tiles = strips * columns;
    if (tiles == 0) return out;
    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    const unsigned threads =
        std::min(settings.threads > 0 ? unsigned(settings.threads) : hardware, unsigned(tiles));
    std::atomic<int> next{0};
    std::exception_ptr failure;
    std::mutex failure_mutex;
    const auto work = [&] {
        try {
            StripFilter filter(planes, settings, first_order);
            for (int t = next.fetch_add(1); t < tiles; t = next.fetch_add(1)) {
                const int y0 = (t / columns) * kStrip, y1 = std::min(y0 + kStrip, planes.height);
                const int x0 = (t % columns) * kTileWidth;
                const int x1 = std::min(x0 + kTileWidth, planes.width);
                // A strip far from anything to average (the emission away from any
                // emitter) is 0 plus the emission: the same bits, without the filter.
                if (planes.zero_rows(y0 - planes.pad, y1 + planes.pad)) {
                    for (int y = y0; y < y1; ++y)
                        for (int x = x0; x < x1; ++x) {
                            const std::size_t i =
                                std::size_t(y) * std::size_t(planes.width) + std::size_t(x);
                            out.pixels[i] =
                                terms.emission.empty() ? glm::vec3(0.0f) : terms.emission[i];
                            if (first_order) {  // select_estimates: 0 either way
                                estimates.mean_a[i] = estimates.mean_b[i] = glm::vec3(0.0f);
                                estimates.fit_a[i] = estimates.fit_b[i] = glm::vec3(0.0f);
                            }
                        }
                    continue;
                }
                filter.run(x0, x1, y0, y1, terms, estimates, out);
            }
        } catch (...) {  // bad_alloc: rethrown on the caller's thread
            const std::lock_guard<std::mutex> lock(failure_mutex);
            if (!failure) failure = std::current_exception();
            next.store(tiles);
        }
    };
    std::vector<std::thread> pool;
    try {
        for (unsigned i = 1; i < threads; ++i) pool.emplace_back(work);
    } catch (const std::system_error& e) {
        next.store(tiles);
        for (std::thread& t : pool) t.join();
        throw Error(std::string("denoise: cannot start threads: ") + e.what());
    }
    work();  // the calling thread works too
    for (std::thread& t : pool) t.join();
    if (failure) std::rethrow_exception(failure);
    if (first_order) select_estimates(planes, terms, estimates, out);
    return out;
}

/// Moves each pixel of `out` back to within settings.max_standard_errors standard errors of
/// the noisy beauty (denoiser.h). Per channel, the variance of a pixel's mean is
/// s (1 - s) (a - b)^2 from its halves (as in make_planes), and the bound uses the larger
/// of the pixel's own and the median of its box's, or the median alone where one half is
/// a few samples and both lie within the range of the 8 neighbours' values
/// (kFootprintRadius). Rows are split among threads;
/// each pixel is computed from the inputs alone, so the bits do not depend on the count.
void bound_by_own_noise(const DenoiserInput& in, const DenoiserSettings& settings, Image& out) {
    const int w = in.beauty.width, h = in.beauty.height;
    const std::size_t n = in.beauty.pixels.size();
    std::vector<glm::vec3> spread(n);
    for (std::size_t i = 0; i < n; ++i) {
        const float s = in.share_a.empty() ? 0.5f : in.share_a[i];
        const glm::vec3 d = in.half_a.pixels[i] - in.half_b.pixels[i];
        spread[i] = d * d * (s * (1.0f - s));
    }
    const float k = settings.max_standard_errors;
    const auto rows = [&](int y0, int y1) {
        std::array<float, std::size_t((2 * kBoundRadius + 1) * (2 * kBoundRadius + 1))> box{};
        for (int y = y0; y < y1; ++y)
            for (int x = 0; x < w; ++x) {
                const std::size_t i = std::size_t(y) * std::size_t(w) + std::size_t(x);
                const float share = in.share_a.empty() ? 0.5f : in.share_a[i];
                const bool few = std::min(share, 1.0f - share) <= kFewSamplesShare;
                for (int c = 0; c < 3; ++c) {
                    std::size_t count = 0;
                    for (int yy = std::max(0, y - kBoundRadius);
                         yy <= std::min(h - 1, y + kBoundRadius); ++yy)
                        for (int xx = std::max(0, x - kBoundRadius);
                             xx <= std::min(w - 1, x + kBoundRadius); ++xx)
                            box[count++] =
                                spread[std::size_t(yy) * std::size_t(w) + std::size_t(xx)][c];
                    const auto mid = box.begin() + std::ptrdiff_t(count / 2);
                    std::nth_element(box.begin(), mid, box.begin() + std::ptrdiff_t(count));
                    // The range of the neighbours' noisy values (not the pixel's own).
                    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
                    for (int yy = std::max(0, y - kFootprintRadius);
                         yy <= std::min(h - 1, y + kFootprintRadius); ++yy)
                        for (int xx = std::max(0, x - kFootprintRadius);
                             xx <= std::min(w - 1, x + kFootprintRadius); ++xx) {
                            if (xx == x && yy == y) continue;
                            const float v =
                                in.beauty
                                    .pixels[std::size_t(yy) * std::size_t(w) + std::size_t(xx)][c];
                            lo = std::min(lo, v);
                            hi = std::max(hi, v);
                        }
                    const float a = in.half_a.pixels[i][c], hb = in.half_b.pixels[i][c];
                    const bool within = few && a >= lo && a <= hi && hb >= lo && hb <= hi;
                    const float variance = within ? *mid : std::max(*mid, spread[i][c]);
                    const float bound = k * std::sqrt(variance);
                    const float b = in.beauty.pixels[i][c];
                    out.pixels[i][c] = std::min(std::max(out.pixels[i][c], b - bound), b + bound);
                }
            }
    };
    const unsigned hardware = std::max(1u, std::thread::hardware_concurrency());
    const unsigned threads = std::max(
        1u, std::min(settings.threads > 0 ? unsigned(settings.threads) : hardware, unsigned(h)));
    std::vector<std::thread> pool;
    const auto band = [&](unsigned t) { return int(std::size_t(h) * t / threads); };
    try {
        for (unsigned t = 1; t < threads; ++t) pool.emplace_back(rows, band(t), band(t + 1));
    } catch (const std::system_error& e) {
        for (std::thread& th : pool) th.join();
        throw Error(std::string("denoise: cannot start threads: ") + e.what());
    }
    rows(band(0), band(1));
    for (std::thread& th : pool) th.join();
}

}  // namespace

void validate(const DenoiserSettings& s) {
    const auto bad = [](const std::string& field, const std::string& value, const char* rule) {
        throw Error("DenoiserSettings." + field + " = " + value + ": " + rule);
    };
    if (s.radius < 1 || s.radius > 32)
        bad("radius", std::to_string(s.radius), "must be in [1, 32]");
    if (s.patch_radius < 0 || s.patch_radius > 8)
        bad("patch_radius", std::to_string(s.patch_radius), "must be in [0, 8]");
    if (!(s.strength > 0.0f && s.strength <= 10.0f))
        bad("strength", std::to_string(s.strength), "must be in (0, 10]");
    if (!(s.albedo_sigma > 0.0f && std::isfinite(s.albedo_sigma)))
        bad("albedo_sigma", std::to_string(s.albedo_sigma), "must be finite and > 0");
    if (!(s.normal_sigma > 0.0f && std::isfinite(s.normal_sigma)))
        bad("normal_sigma", std::to_string(s.normal_sigma), "must be finite and > 0");
    if (!(s.max_standard_errors >= 0.0f && s.max_standard_errors <= 100.0f))
        bad("max_standard_errors", std::to_string(s.max_standard_errors), "must be in [0, 100]");
    if (s.threads < 0 || s.threads > 1024)
        bad("threads", std::to_string(s.threads), "must be in [0, 1024]");
}

DenoiserInput denoiser_input(const Film& first, const Film& full) {
    if (first.width != full.width || first.height != full.height) {
        throw Error("denoiser_input: the first film is " + std::to_string(first.width) + " x " +
                    std::to_string(first.height) + ", the full one " + std::to_string(full.width) +
                    " x " + std::to_string(full.height));
    }
    if (!full.has_aovs()) throw Error("denoiser_input: the full film has no AOVs");
    if (!first.has_aovs()) throw Error("denoiser_input: the first film has no AOVs");
    const ImageLayers layers = resolve_layers(full);
    const ImageLayers first_layers = resolve_layers(first);
    DenoiserInput in;
    in.beauty = layers.beauty;
    in.albedo = layers.albedo;
    in.normal = layers.normal;
    in.half_a = resolve(first);
    in.half_b = Image(full.width, full.height);
    in.albedo_a = first_layers.albedo;
    in.normal_a = first_layers.normal;
    in.albedo_b = Image(full.width, full.height);
    in.normal_b = Image(full.width, full.height);
    in.emission_a = Image(full.width, full.height);
    in.emission_b = Image(full.width, full.height);
    in.share_a.resize(full.pixels.size());
    // The splats' part of each half: resolve() divides them by the mean sample count, so
    // the second part's splats are (full's x N - first's x N1) / (N - N1).
    Image splat_full, splat_first;
    double n_full = 0.0, n_first = 0.0;
    if (full.splats && first.splats) {
        n_full = splat_samples_per_pixel(full);
        n_first = splat_samples_per_pixel(first);
        splat_full = full.splats->resolve(n_full);
        splat_first = first.splats->resolve(n_first);
    }
    for (std::size_t i = 0; i < full.pixels.size(); ++i) {
        const FilmPixel& a = first.pixels[i];
        const FilmPixel& f = full.pixels[i];
        if (a.samples == 0 || f.samples <= a.samples) {
            const auto w = static_cast<std::size_t>(full.width);
            throw Error("denoiser_input: pixel (" + std::to_string(i % w) + ", " +
                        std::to_string(i / w) + ") holds " + std::to_string(a.samples) +
                        " samples in the first film and " + std::to_string(f.samples) +
                        " in the full one: needs at least 1 and more than that");
        }
        in.share_a[i] = float(double(a.samples) / double(f.samples));
        const std::uint32_t rest = f.finite - std::min(f.finite, a.finite);
        glm::dvec3 b = rest > 0 ? (f.radiance - a.radiance) / double(rest) : glm::dvec3(0.0);
        if (!splat_full.pixels.empty() && n_full > n_first) {
            b += (glm::dvec3(splat_full.pixels[i]) * n_full -
                  glm::dvec3(splat_first.pixels[i]) * n_first) /
                 (n_full - n_first);
        }
        in.half_b.pixels[i] = glm::vec3(b);
        // The second part's AOV means, as resolve_layers takes them: the albedo over the
        // sum of the filter weights' signs, the normal over the samples.
        const AovPixel& aa = first.aovs[i];
        const AovPixel& af = full.aovs[i];
        const double signs = (double(f.samples) - 2.0 * double(af.negative)) -
                             (double(a.samples) - 2.0 * double(aa.negative));
        in.albedo_b.pixels[i] =
            signs != 0.0 ? glm::vec3((af.albedo - aa.albedo) / signs) : glm::vec3(0.0f);
        in.normal_b.pixels[i] = glm::vec3((af.normal - aa.normal) / double(f.samples - a.samples));
        // Emission: the samples' mean, as the beauty's radiance.
        in.emission_a.pixels[i] = glm::vec3(aa.emission / double(a.samples));
        in.emission_b.pixels[i] =
            glm::vec3((af.emission - aa.emission) / double(f.samples - a.samples));
    }
    return in;
}

Image denoise(const DenoiserInput& input, const DenoiserSettings& settings) {
    validate(settings);
    check_input(input);
    const int w = input.beauty.width, h = input.beauty.height;
    Image ones(w, h);
    for (glm::vec3& p : ones.pixels) p = glm::vec3(1.0f);
    // A layer filtered on its own two halves alone (no features, nothing to demodulate).
    // Equal halves come back unchanged.
    const auto filter_alone = [&](const Image& half_a, const Image& half_b,
                                  const DenoiserSettings& with) {
        DenoiserInput alone;
        alone.beauty = half_a;  // its size; the filter reads the halves
        alone.half_a = half_a;
        alone.half_b = half_b;
        alone.share_a = input.share_a;
        alone.albedo = ones;
        alone.normal = Image(w, h);
        return filter_halves(alone, ones, with, Image(), false);
    };
    // The albedo is prefiltered first, as Rousselle et al. 2013 and NFOR prefilter their
    // features: where a texture or an outline crosses a pixel, its albedo is the share of
    // its samples that saw each side, as noisy as the radiance, and multiplying the
    // filtered radiance back by it would bring that noise back.
    DenoiserSettings prefilter = settings;
    prefilter.radius = std::min(settings.radius, kPrefilterRadius);
    prefilter.strength = kPrefilterStrength;
    const Image albedo = input.albedo_a.pixels.empty()
                             ? input.albedo
                             : filter_alone(input.albedo_a, input.albedo_b, prefilter);
    // The emission is filtered apart from the light reflected (DenoiserInput::emission_a):
    // an emitter's pixels average only emission, whose noise is its edges' coverage, and
    // give none of it to their neighbours' reflected light. With the radiance's settings:
    // the prefilter's smaller, stronger ones left the synthesis' sphere light's edge noisier
    // (relMSE 4.2x lower at 16 spp instead of 12.1x). Skipped when nothing emits.
    Image emission;
    if (!input.emission_a.pixels.empty()) {
        const auto emits = [](const Image& im) {
            return std::any_of(im.pixels.begin(), im.pixels.end(),
                               [](const glm::vec3& v) { return v != glm::vec3(0.0f); });
        };
        if (emits(input.emission_a) || emits(input.emission_b))
            emission = filter_alone(input.emission_a, input.emission_b, settings);
    }
    Image out = filter_halves(input, albedo, settings, emission, settings.first_order);
    if (settings.max_standard_errors > 0.0f) bound_by_own_noise(input, settings, out);
    return out;
}

}  // namespace librt
