// The per-pixel memory figures the apps check --size against (issue 37, defect 5) are
// the sizes of the records the renderer allocates, added up as docs/robustness.md says.

#include <librt/core/image.h>
#include <librt/film/film.h>
#include <librt/render/render_memory.h>

#include <gtest/gtest.h>

#include <glm/ext/vector_double3.hpp>

#include <cstdint>

using namespace librt;

TEST(RenderMemory, ProgressiveCountsTheFilmItsCopyAndTheImage) {
    constexpr std::uint64_t film = sizeof(FilmPixel);
    constexpr std::uint64_t aov = sizeof(AovPixel);
    constexpr std::uint64_t splat = 3 * sizeof(std::int64_t);
    constexpr std::uint64_t image = sizeof(glm::vec3);
    EXPECT_EQ(film, 32u);  // the figures of docs/robustness.md
    EXPECT_EQ(aov, 88u);
    RenderMemoryOptions o;
    EXPECT_EQ(progressive_bytes_per_pixel(o), 2 * film + image);  // 76
    o.aovs = true;
    EXPECT_EQ(progressive_bytes_per_pixel(o), 2 * (film + aov) + image);  // 252
    o.splats = true;  // the splat sums travel with both films; their image joins the means
    EXPECT_EQ(progressive_bytes_per_pixel(o), 2 * (film + aov + splat) + 2 * image);
    o = {};
    o.adaptive = true;  // a third film and the tables that pick the counts
    EXPECT_EQ(progressive_bytes_per_pixel(o),
              3 * film + 3 * sizeof(double) + 2 * sizeof(std::uint32_t) + image);
    o = {};
    o.keeps_training = true;  // the half film and the weighted sums (and their copy)
    EXPECT_EQ(progressive_bytes_per_pixel(o), 3 * film + 2 * sizeof(glm::dvec3) + image);
    o = {};
    o.noise_estimate = true;  // NoiseEstimate's snapshot of the pixels and their variances
    EXPECT_EQ(progressive_bytes_per_pixel(o), 3 * film + sizeof(float) + image);  // 112
}

TEST(RenderMemory, RenderCountsOneFilmAndTheImage) {
    RenderMemoryOptions o;
    EXPECT_EQ(render_bytes_per_pixel(o), sizeof(FilmPixel) + sizeof(glm::vec3));  // 44
    o.aovs = true;  // render() keeps no AOVs
    EXPECT_EQ(render_bytes_per_pixel(o), sizeof(FilmPixel) + sizeof(glm::vec3));
    o = {};
    o.keeps_training = true;
    EXPECT_EQ(render_bytes_per_pixel(o),
              2 * sizeof(FilmPixel) + 2 * sizeof(glm::dvec3) + sizeof(glm::vec3));
}
