// render_block onto a film that holds only a region of the image (FilmOrigin): what
// render_mpi's workers do so that none of them allocates the whole frame. Every tile film,
// copied into a film of the whole image, must equal the one-shot render bit for bit.

#include "render/film_test_util.h"

#include <librt/core/error.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <string>

using namespace librt;
using librt::testing::film_test_camera;
using librt::testing::film_test_scene;
using librt::testing::same_records;

namespace {

constexpr std::uint32_t kSpp = 6;

BlockSettings settings_of(int threads, int tile) {
    BlockSettings s;
    s.threads = threads;
    s.tile_size = tile;
    s.seed = 99;
    return s;
}

// Copies the records of `tile` (placed at `origin`) into `whole`, row by row.
void paste(Film& whole, const Film& tile, FilmOrigin origin) {
    for (int y = 0; y < tile.height; ++y) {
        for (int x = 0; x < tile.width; ++x) {
            whole.at(origin.x + x, origin.y + y) = tile.at(x, y);
            if (tile.has_aovs())
                whole.aovs[whole.index(origin.x + x, origin.y + y)] = tile.aovs[tile.index(x, y)];
        }
    }
}

class FilmRegion : public ::testing::Test {
protected:
    FilmRegion() : scene_(film_test_scene()), camera_(film_test_camera()) {
        integrator_.preprocess(scene_);
    }

    Film one_shot(std::uint32_t spp) {
        Film film(camera_.width(), camera_.height(), true);
        const RenderStats st =
            render_block(scene_, camera_, integrator_, film,
                         {0, 0, film.width, film.height, 0, spp}, settings_of(2, 16));
        EXPECT_EQ(st.samples_per_pixel, spp);
        return film;
    }

    Scene scene_;
    Camera camera_;
    librt::testing::WideRangeIntegrator integrator_;
};

}  // namespace

// Square tiles of several sides (edge tiles cut by the 29 x 19 image), each on a film of
// its own size, rendered by 1 to 3 threads with thread tiles smaller and larger than it.
TEST_F(FilmRegion, TileFilmsPastedTogetherEqualTheOneShotFilm) {
    const Film reference = one_shot(kSpp);
    for (const int side : {1, 5, 8, 32}) {
        for (const int threads : {1, 3}) {
            Film whole(camera_.width(), camera_.height(), true);
            std::uint64_t samples = 0;
            for (int y0 = 0; y0 < camera_.height(); y0 += side) {
                for (int x0 = 0; x0 < camera_.width(); x0 += side) {
                    const int x1 = std::min(x0 + side, camera_.width());
                    const int y1 = std::min(y0 + side, camera_.height());
                    Film tile(x1 - x0, y1 - y0, true);
                    const RenderStats st =
                        render_block(scene_, camera_, integrator_, tile, {x0, y0},
                                     {x0, y0, x1, y1, 0, kSpp}, settings_of(threads, 3));
                    samples += st.samples;
                    paste(whole, tile, {x0, y0});
                }
            }
            EXPECT_EQ(samples,
                      std::uint64_t(camera_.width()) * std::uint64_t(camera_.height()) * kSpp);
            EXPECT_TRUE(same_records(whole, reference))
                << "side " << side << ", " << threads << " threads";
        }
    }
}

// A block smaller than the film's region, and samples continued in two ranges: only the
// block's pixels change, and they equal the one-shot film's.
TEST_F(FilmRegion, BlocksWithinTheRegionContinueItsPixels) {
    const Film reference = one_shot(kSpp);
    const FilmOrigin origin{7, 4};
    Film tile(12, 10, true);
    const Film empty = tile;
    (void)render_block(scene_, camera_, integrator_, tile, origin, {9, 6, 15, 11, 0, 2},
                       settings_of(2, 4));
    (void)render_block(scene_, camera_, integrator_, tile, origin, {9, 6, 15, 11, 2, kSpp - 2},
                       settings_of(1, 64));
    for (int y = 0; y < tile.height; ++y) {
        for (int x = 0; x < tile.width; ++x) {
            const int ix = origin.x + x;
            const int iy = origin.y + y;
            const bool inside = ix >= 9 && ix < 15 && iy >= 6 && iy < 11;
            const FilmPixel& want = inside ? reference.at(ix, iy) : empty.at(x, y);
            const AovPixel& want_aov =
                inside ? reference.aovs[reference.index(ix, iy)] : empty.aovs[empty.index(x, y)];
            EXPECT_EQ(std::memcmp(&tile.at(x, y), &want, sizeof want), 0) << ix << ", " << iy;
            EXPECT_EQ(std::memcmp(&tile.aovs[tile.index(x, y)], &want_aov, sizeof want_aov), 0)
                << ix << ", " << iy;
        }
    }
}

TEST_F(FilmRegion, RegionsAndBlocksOutsideAreRefusedBeforeRendering) {
    Film tile(8, 8, false);
    const Film before = tile;
    const auto expect_error = [&](FilmOrigin origin, const RenderBlock& b,
                                  const std::string& text) {
        try {
            (void)render_block(scene_, camera_, integrator_, tile, origin, b, settings_of(1, 4));
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
        EXPECT_TRUE(same_records(tile, before)) << text;
    };
    // The 29 x 19 image cannot hold an 8 x 8 film at (22, 0) or (0, 12), nor at (-1, 0).
    expect_error({22, 0}, {22, 0, 30, 8, 0, 1}, "film region [22, 30) x [0, 8)");
    expect_error({0, 12}, {0, 12, 8, 20, 0, 1}, "must lie in the camera's 29 x 19 image");
    expect_error({-1, 0}, {0, 0, 7, 8, 0, 1}, "film region [-1, 7)");
    // Blocks reaching outside the film's region [4, 12) x [4, 12).
    expect_error({4, 4}, {3, 4, 12, 12, 0, 1}, "must lie in the 8 x 8 film placed at (4, 4)");
    expect_error({4, 4}, {4, 4, 12, 13, 0, 1}, "block [4, 12) x [4, 13)");
    // A pixel that does not hold block.first samples.
    expect_error({4, 4}, {4, 4, 12, 12, 1, 1}, "film pixel (4, 4) holds 0 samples");
}
