#pragma once

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/film/film.h>

#include <vector>

// A denoiser of our own, guided by the AOVs: a feature-guided non-local-means filter with
// cross-filtered half buffers (Rousselle, Knaus & Zwicker 2012, "Adaptive rendering with
// non-local means filtering"; the half buffers and their cross-filtering as in Rousselle,
// Manzi & Zwicker 2013 and Bitterli et al. 2016, NFOR).
//
// Why this design (and not a neural network: there is none to ship, and OIDN is not in
// Debian 12):
//  - The film keeps sums, not squared sums, so a pixel's noise is estimated from two
//    disjoint halves of its samples: (a - b)^2 measures it without any assumption about
//    the image. The denoiser needs no tuning per scene.
//  - Demodulation: the patches are compared on the beauty divided by the albedo (the first
//    non-specular hit's reflectance), and a pixel's output is its albedo times the
//    neighbours' radiance over their albedo, both averaged with its weights (a ratio of
//    averages, not an average of ratios: a dark-albedo neighbour, such as an emitter's
//    edge, is not multiplied up on its own). Textures live in the albedo, which is nearly
//    noise-free, so they come back sharp; only the illumination is smoothed, and
//    illumination is smooth where the features are.
//  - Emission apart: what the first hits emit (the emission AOV) is taken out of the
//    halves and filtered on its own, then added back; emitted light is not albedo x light
//    arriving, so demodulated with the rest it moved light across an emitter's edge.
//  - Non-local means: a neighbour q counts for pixel p as much as the patch around q looks
//    like the patch around p, measured in units of their noise (the distance of two noisy
//    patches minus what their noise alone explains). Where the noise is zero, only
//    identical patches count: a noise-free image comes back unchanged.
//  - Features: a neighbour whose albedo or normal differs from p's (another object, the
//    other side of an edge) gets a small weight, so geometric and texture edges are kept.
//    The features are noisy too where an edge crosses a pixel (the share of its samples
//    on each side): their own noise, from their halves, and their local gradient widen
//    the tolerance there (Rousselle, Manzi & Zwicker 2013), and the albedo is prefiltered
//    by this same filter before the radiance is multiplied back by it, else that
//    coverage noise would come back with it.
//    A direct-light visibility feature (NFOR's: one light sample's shadow ray per camera
//    sample), as a feature weight or as a covariate of the first-order fit, was measured
//    and not kept: dragons_instanced.glb 1.8x -> 1.9x at 64 spp, nothing elsewhere
//    (docs/benchmarks.md, "A direct-light visibility feature").
//  - First order (Moon et al. 2014, "Adaptive rendering based on weighted local
//    regression"; NFOR): with the weights above, each pixel also fits its neighbours'
//    demodulated radiance as a + b . (q - p), linear in their offset (ridge-regularised),
//    whose a, the fit at the pixel, has no bias on a slope where the weighted mean is
//    pulled toward the side with more (or more alike) neighbours, e.g. at the image's
//    edge. The fit has more variance where few neighbours weigh, so each pixel keeps the
//    fit or the mean, whichever differs less from the other half's noisy values over its
//    9 x 9 box (NFOR selects among its filters the same way). The pixel's own weight in
//    its fit is its most alike neighbour's, not 1 (Buades et al. 2005): a pixel whose half
//    caught a firefly is like none of its neighbours and kept its value with weight 1.
//  - Cross-filtering: each half is filtered with weights computed from the other half, so
//    a pixel's weights are independent of the noise they average (no "filtering towards
//    the noise" bias; NFOR's argument), and the two filtered halves are averaged.
//  - Bounded by each pixel's own noise: the output stays within max_standard_errors
//    standard errors of the pixel's noisy value. The standard error is the larger of the
//    pixel's own (from its halves) and the median of its 5 x 5 box's: the median ignores a
//    few noisy neighbours, so a converged highlight among them keeps a tight bound (the
//    plain filter pulled material_spheres.glb's one-pixel highlights from 21 to 6), while
//    a firefly's own large spread leaves it free to go. A pixel whose halves agree by
//    chance gets its box's median, so noise is still removed. Where one half is a few
//    samples (adaptive sampling's first part) and both halves lie within the range of the
//    pixel's 8 neighbours, their difference may be where in the pixel those few samples
//    fell, which the rest average out: the pixel gets its box's median alone (a converged
//    highlight's edge was pulled 10.7 -> 9.1 by its own spread; docs/benchmarks.md).
//  - Deterministic and multithreaded: every output pixel is computed by one thread from
//    the inputs alone, its neighbours visited in a fixed order; the thread count changes
//    which thread computes a pixel, never its arithmetic.

namespace librt {

/// What the denoiser reads. All images have the beauty's size, row-major, top row first.
struct DenoiserInput {
    Image beauty;  ///< the noisy estimate: the mean of all of a pixel's samples
    Image albedo;  ///< albedo AOV (resolve_layers): what the first non-specular hit reflects
    Image normal;  ///< normal AOV: unit world-space shading normal, 0 for a miss
    Image half_a;  ///< mean of the first part of each pixel's samples
    Image half_b;  ///< mean of the rest of them (disjoint from half_a's)
    /// Per pixel, the fraction of its samples in half_a, in (0, 1); empty = 0.5 everywhere.
    /// beauty = share_a x half_a + (1 - share_a) x half_b.
    std::vector<float> share_a;
    /// The albedo AOV of half_a's samples and of half_b's, or both 0x0 (then `albedo`
    /// stands for both, and its noise is taken as 0). Each half is demodulated by its own
    /// albedo: a pixel on a texture edge sees the two colours in different proportions in
    /// its two halves, and in the radiance of each exactly as in its albedo.
    Image albedo_a;
    Image albedo_b;  ///< see albedo_a
    /// The normal AOV of half_a's samples and of half_b's, or both 0x0: their difference
    /// says how noisy the normal is (a silhouette), which widens the tolerance of the
    /// normal weight there.
    Image normal_a;
    Image normal_b;  ///< see normal_a
    /// The radiance the first hits emit (AovPixel::emission), of half_a's samples and of
    /// half_b's, or both 0x0 (then none). It is taken out of each half before filtering and
    /// added back after, unfiltered: emitted light is not the albedo times the light
    /// arriving, so demodulated with the rest it made the pixels on an emitter's edge take
    /// in the emitter (or the emitter its dark surround) and come back off by the ratio of
    /// their albedos (cornell_pbr.glb's panel, docs/benchmarks.md).
    Image emission_a;
    Image emission_b;  ///< see emission_a
};

/// The denoiser's parameters. The defaults are what docs/benchmarks.md measures.
struct DenoiserSettings {
    /// Half side of the square of neighbours averaged, in [1, 32]: (2r + 1)^2 of them. The
    /// cost grows with its square.
    int radius = 8;
    /// Half side of the patches compared, in [0, 8].
    int patch_radius = 3;
    /// How much patch differences beyond the noise are tolerated, in (0, 10]: larger
    /// smooths more (Rousselle et al.'s k; 0.45 in their paper).
    float strength = 0.45f;
    /// Albedo difference (RGB distance) at which a neighbour's weight falls to 1/e, > 0.
    float albedo_sigma = 0.1f;
    /// Normal difference (distance of unit vectors) at which a neighbour's weight falls to
    /// 1/e, > 0.
    float normal_sigma = 0.3f;
    /// How far a pixel may move, in standard errors of its own mean, in [0, 100]; 0 = no
    /// bound. A pixel the noisy image already has right (a converged highlight beside dim,
    /// noisy pixels) is then not pulled toward its neighbours, and the filter's bias
    /// vanishes as the samples grow. See denoise().
    float max_standard_errors = 3.0f;
    /// Fit the neighbours' radiance as linear in their offset (a first-order weighted
    /// regression) where that errs less than averaging it: a gradient (light falling off
    /// across a wall, an image edge with neighbours on one side) comes back without the
    /// weighted mean's bias. false: the weighted mean alone, which costs less
    /// (docs/benchmarks.md).
    bool first_order = true;
    int threads = 0;  ///< worker threads in [0, 1024]; 0 = hardware_concurrency()
};

/// Throws librt::Error naming the first bad field and its value.
LIBRT_API void validate(const DenoiserSettings& settings);

/// The denoiser's input from a render's films: `first` is the film as it was part way
/// (every pixel holding fewer samples than in `full`, at least one), `full` the film at
/// the end, both with AOVs. half_a is resolve(first), half_b the mean of the samples `full`
/// has beyond it (from the difference of the sums, splats included in proportion), beauty
/// resolve(full), and the AOVs (albedo, normal, emission) of each half likewise. Throws
/// librt::Error when the sizes differ, a film has no AOVs, or a pixel does not hold more samples in
/// `full` than in `first` (naming the pixel).
[[nodiscard]] LIBRT_API DenoiserInput denoiser_input(const Film& first, const Film& full);

/// The denoised beauty. Throws librt::Error naming the layer when a layer's size is not
/// the beauty's, a value is not finite (naming the pixel), or share_a is out of range;
/// and for invalid settings. The same bits for any thread count.
[[nodiscard]] LIBRT_API Image denoise(const DenoiserInput& input,
                                      const DenoiserSettings& settings = {});

}  // namespace librt
