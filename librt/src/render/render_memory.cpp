#include <librt/core/image.h>
#include <librt/film/film.h>
#include <librt/render/render_memory.h>

#include <glm/ext/vector_double3.hpp>

#include <cstdint>

namespace librt {

namespace {

// Each term is a record the renderer allocates per pixel (renderer.cpp, film.cpp,
// adaptive_sampling.cpp, pass_combination.cpp).
constexpr std::uint64_t kFilm = sizeof(FilmPixel);
constexpr std::uint64_t kAov = sizeof(AovPixel);
constexpr std::uint64_t kSplat = 3 * sizeof(std::int64_t);  // SplatFilm: r, g, b sums
constexpr std::uint64_t kImage = sizeof(glm::vec3);         // Image's pixel
constexpr std::uint64_t kKept = sizeof(glm::dvec3);         // PassCombination's sum
// adaptive_sample_counts: the halves' difference, its summed-area table and the noise, in
// double, and the counts it returns; render_progressive adds each pass's goals.
constexpr std::uint64_t kAdaptive = 3 * sizeof(double) + 2 * sizeof(std::uint32_t);

// The image at the end: resolve() makes the pixel means and, with splats, the splat image
// it adds to them.
std::uint64_t image_bytes(const RenderMemoryOptions& o) { return kImage + (o.splats ? kImage : 0); }

// Kept training passes: the film at half the samples (radiance and splats), the weighted
// sums, and the copy of them combined() joins the image to.
std::uint64_t kept_bytes(const RenderMemoryOptions& o) {
    return kFilm + (o.splats ? kSplat : 0) + 2 * kKept;
}

}  // namespace

std::uint64_t render_bytes_per_pixel(const RenderMemoryOptions& o) {
    // render()'s film has no AOVs; adaptive sampling and kept passes exclude each other
    // (a kept pass needs the same count in every pixel), so the larger extra is counted.
    const std::uint64_t film = kFilm + (o.splats ? kSplat : 0);
    std::uint64_t extra = 0;
    if (o.adaptive) extra = film + kAdaptive;  // the film at half the pilot
    if (o.keeps_training) extra = extra > kept_bytes(o) ? extra : kept_bytes(o);
    return film + extra + image_bytes(o);
}

std::uint64_t progressive_bytes_per_pixel(const RenderMemoryOptions& o) {
    const std::uint64_t film = kFilm + (o.aovs ? kAov : 0) + (o.splats ? kSplat : 0);
    std::uint64_t extra = 0;
    if (o.adaptive) extra = film + kAdaptive;  // the film at half the pilot
    if (o.keeps_training) extra = extra > kept_bytes(o) ? extra : kept_bytes(o);
    const std::uint64_t noise = o.noise_estimate ? kFilm + sizeof(float) : 0;  // NoiseEstimate
    return 2 * film + extra + image_bytes(o) + noise;  // the film and the pass's copy of it
}

}  // namespace librt
