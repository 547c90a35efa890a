#pragma once

#include <librt/core/image.h>
#include <librt/core/image_layers.h>
#include <librt/export.h>
#include <librt/film/splat_film.h>

#include <glm/ext/vector_double3.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

// An accumulation film: per-pixel sums and sample counts, not means, so that a render can
// be split by pixel region and by sample range and put back together exactly.
//
// Why a split render equals the one-shot render bit for bit:
//  - A pixel's radiance sum is a double accumulated strictly in sample-index order
//    (sum_k = sum_{k-1} + double(sample_k); a float converts to double exactly), and the
//    film stores that running sum with the number of samples it holds. Rendering samples
//    [first, first + count) onto a film whose pixel holds exactly `first` samples
//    continues the very same chain of additions, so rendering [0, a) then [a, b) onto one
//    film does the same additions in the same order as rendering [0, b) at once: same
//    bits. A sample range is never summed on its own and then added: double addition is
//    not associative, and although floats summed in double are mostly exact, samples more
//    than ~2^29 apart in one pixel (a light seen directly beside dim indirect light) round,
//    differently in each order. That is why merge() refuses two films that both hold
//    samples of one pixel.
//  - Each pixel is computed independently of every other (its samples are seeded by
//    (pixel, sample index, seed), never by thread, tile or region), so disjoint regions
//    rendered anywhere and merged by copying their pixel records give the same records.
//  - resolve() turns a record into the same float mean the renderer always produced:
//    float(sum / finite).
// The AOV sums (albedo, normal, depth) are accumulated the same way, in the same order.
//
// Splats (Integrator::splats: light tracing, bidirectional path tracing) land on any pixel
// from any thread, so they cannot join a pixel's ordered chain: the film keeps them apart,
// in a SplatFilm of integer sums over the whole image, which any order, split or merge adds
// exactly (splat_film.h). resolve() adds them to the pixel means, divided by the render's
// samples per pixel (splat_samples_per_pixel below): every pixel's sample count once the
// render is complete, the mean count when it stopped early.

namespace librt {

/// What the film holds for one pixel: the running sum of its finite radiance samples and
/// how many samples it holds. 32 bytes.
struct FilmPixel {
    glm::dvec3 radiance{0.0};   ///< sum of the finite samples, added in sample order
    std::uint32_t samples = 0;  ///< samples taken: the pixel holds samples [0, samples)
    std::uint32_t finite = 0;   ///< how many of them were finite (and are in `radiance`)
};

/// The AOV sums of one pixel, accumulated over the same samples as its FilmPixel (all of
/// them, including those whose radiance was not finite). 88 bytes.
///
/// The pixel filter: sample positions are drawn from |f| (filter importance sampling),
/// so every sum below is already |f|-weighted. The albedo also takes the sign of the
/// sample's filter weight (negative only in a Mitchell filter's lobes; the weight's size is
/// the same for every sample of a filter), and resolve_layers divides it by the sum of the
/// signs: the filtered mean sum(w a) / sum(w), like a colour pass of pbrt-v4's film, exact
/// on a constant albedo. Normal and depth stay |f|-weighted means: a signed mean of
/// geometry can leave the range the pixel sees (a negative depth, a normal longer than 1).
struct AovPixel {
    /// Sum of the albedos (bsdf.h, denoising_albedo) of the first non-specular hits (0 for
    /// a miss), each with the sign of its sample's filter weight.
    glm::dvec3 albedo{0.0};
    glm::dvec3 normal{0.0};      ///< sum of their unit world-space shading normals (0: miss)
    double depth = 0.0;          ///< sum of the planar camera depths of the first hits
    std::uint32_t hits = 0;      ///< samples whose camera ray hit something (the terms of `depth`)
    std::uint32_t negative = 0;  ///< samples whose filter weight was negative (Mitchell's lobes)
    /// Sum of the radiance emitted by the camera rays' first hits (0 where it emits nothing),
    /// times each sample's filter weight as the beauty's: the part of the beauty that is
    /// not light reflected, which the denoiser keeps out of its albedo demodulation.
    glm::dvec3 emission{0.0};
};

/// Per-pixel sums of a render, row-major with the top row first like Image. Plain data:
/// it can be copied, sent between machines and merged.
struct LIBRT_API Film {
    int width = 0;                  ///< pixels per row
    int height = 0;                 ///< number of rows
    std::vector<FilmPixel> pixels;  ///< width * height records, top row first
    std::vector<AovPixel> aovs;     ///< width * height AOV records, or empty for no AOVs
    /// The splats of an integrator that splats, over the whole image (the camera's size,
    /// also when this film holds only a region of it); empty for one that does not. The
    /// render loop creates it on the first block it renders with such an integrator.
    std::optional<SplatFilm> splats;

    /// An empty 0x0 film.
    Film() = default;
    /// An empty width x height film (every pixel holds 0 samples), with AOV records when
    /// `with_aovs`. Throws librt::Error naming the size when a side is negative or the
    /// film would exceed kMaxBytes, before allocating anything.
    Film(int width, int height, bool with_aovs = false);

    /// Largest film the constructor allocates: 16 GiB of records.
    static constexpr std::uint64_t kMaxBytes = std::uint64_t{16} << 30u;

    /// True when the film keeps AOV sums.
    [[nodiscard]] bool has_aovs() const { return !aovs.empty(); }
    /// Index of pixel (x, y) in `pixels` and `aovs`. Unchecked.
    [[nodiscard]] std::size_t index(int x, int y) const {
        return static_cast<std::size_t>(y) * static_cast<std::size_t>(width) +
               static_cast<std::size_t>(x);
    }
    /// Pixel (x, y): column x, row y from the top. Unchecked.
    [[nodiscard]] FilmPixel& at(int x, int y) { return pixels[index(x, y)]; }
    /// Pixel (x, y): column x, row y from the top. Unchecked.
    [[nodiscard]] const FilmPixel& at(int x, int y) const { return pixels[index(x, y)]; }
};

/// Copies into `into` every pixel record of `from` that holds samples, and adds `from`'s
/// splat sums to `into`'s (integers: exact, whatever the split). For pixels that hold
/// samples in both films this cannot be exact (see the top of this header), so it throws
/// librt::Error naming the pixel; render the later samples onto the film instead
/// (render_block continues a film). Also throws when the sizes differ, only one of the
/// films has AOVs, or the splat films differ in size, filter or scale. `into` is unchanged
/// when it throws.
LIBRT_API void merge(Film& into, const Film& from);

/// The divisor of a film's splat sums: the camera samples per pixel of the render, the
/// total over its pixels divided by their number. Every pixel's count for a complete render
/// (bit for bit, however it was split); the mean count for one stopped early, which keeps
/// the splats an unbiased estimate when each camera sample brings one light path
/// (splat_film.h). 0 for a film holding no samples.
[[nodiscard]] LIBRT_API double splat_samples_per_pixel(const Film& film);

/// The image: each pixel the mean of its finite radiance samples, float(sum / finite),
/// black when it has none; plus, when the film has splats, splats->resolve(
/// splat_samples_per_pixel(film)) (a float addition; nothing for a film of no samples).
/// Throws librt::Error when the splat film's size is not the film's (a region film, whose
/// splats cover the whole image: merge it into a whole-image film first).
[[nodiscard]] LIBRT_API Image resolve(const Film& film);

/// Every layer of the film: beauty (resolve()), the per-pixel sample count, and when the
/// film has AOVs, albedo (the filter-weighted mean over all samples of the pixel, a miss
/// counting as 0: the albedo sum divided by samples - 2 negative, the sum of the weights'
/// signs; 0 when that is 0), normal (world space, mean over all samples, a miss counting as
/// 0) and depth (mean planar depth, the distance from the camera's lens plane along its
/// optical axis, over the samples that hit; +infinity when none did).
[[nodiscard]] LIBRT_API ImageLayers resolve_layers(const Film& film);

/// The number of samples every pixel of the film holds; throws librt::Error naming a
/// pixel that holds a different number than pixel (0, 0). 0 for an empty film.
[[nodiscard]] LIBRT_API std::uint32_t uniform_sample_count(const Film& film);

}  // namespace librt
