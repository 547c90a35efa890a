// librt::render_mpi inside whatever MPI job runs this binary: alone (ctest's RenderMpi.*,
// also under ThreadSanitizer, where rank 0 renders on its own thread while its main thread
// polls, the part of render_mpi that has threads) and under mpirun -np 3 (ctest
// mpi.render_mpi_np3). On rank 0 the film must equal a one-process render_block film bit
// for bit; the other ranks get an empty film.
#include "render/film_test_util.h"
#include "render/splat_test_util.h"

#include <librt/core/error.h>
#include <librt/integrator/integrators.h>
#include <librt/mpi/render_mpi.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <mpi.h>

#include <algorithm>
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <string>

using namespace librt;
using librt::testing::film_test_camera;
using librt::testing::film_test_scene;
using librt::testing::same_pixels;
using librt::testing::same_records;

namespace {

int world_rank() {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank;
}

bool same_splats(const Film& a, const Film& b) {
    return a.splats.has_value() == b.splats.has_value() &&
           (!a.splats || a.splats->sums() == b.splats->sums());
}

Scene empty_scene() {
    Scene scene;
    scene.commit();
    return scene;
}

// Splats anywhere (partly off the film) with a Gaussian filter, and own-pixel colours.
librt::testing::RandomSplatter::Options splatter_options(bool trains) {
    librt::testing::RandomSplatter::Options o;
    o.margin = 3.0f;
    o.trains = trains;
    return o;
}

// render_mpi's settings for one case of a test's loops.
MpiRenderSettings split(const RenderSettings& rs, int threads, int tile, bool root_renders,
                        bool aovs = false) {
    MpiRenderSettings s;
    s.render = rs;
    s.render.threads = threads;
    s.tile_size = tile;
    s.root_renders = root_renders;
    s.aovs = aovs;
    return s;
}

}  // namespace

TEST(RenderMpi, FilmEqualsTheOneProcessFilmForAnyTileAndThreadCount) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera();
    librt::testing::WideRangeIntegrator integrator;
    constexpr std::uint32_t kSpp = 5;
    Film reference(camera.width(), camera.height(), true);
    integrator.preprocess(scene);
    BlockSettings one;
    one.threads = 2;
    one.seed = 11;
    (void)render_block(scene, camera, integrator, reference,
                       {0, 0, camera.width(), camera.height(), 0, kSpp}, one);
    for (const int tile : {1, 7, 32}) {
        for (const int threads : {1, 2}) {
            MpiRenderSettings s;
            s.render.samples_per_pixel = static_cast<int>(kSpp);
            s.render.adaptive.enabled = false;  // every pixel the block's kSpp samples
            s.render.seed = 11;
            s.render.threads = threads;
            s.render.tile_size = 3;
            s.tile_size = tile;
            s.aovs = true;
            MpiRenderStats stats;
            const Film film = render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s, &stats);
            EXPECT_FALSE(stats.cancelled);
            if (world_rank() == 0) {
                EXPECT_TRUE(same_records(film, reference))
                    << "tile " << tile << ", threads " << threads;
                int sum = 0;
                for (const int n : stats.tiles_per_rank) sum += n;
                EXPECT_EQ(sum, stats.tiles);
            } else {
                EXPECT_EQ(film.width, 0);
                EXPECT_TRUE(film.pixels.empty());
            }
        }
    }
}

// Path guiding that keeps its training passes: rank 0 keeps them and the tiles travel
// with their records at half the samples, so the image render_mpi returns is render()'s
// bit for bit, for any tile size, thread count and number of ranks (ctest runs this alone,
// with 2 and with 3 ranks), and the film holds the image's own samples.
TEST(RenderMpi, KeptTrainingPassesGiveRendersImage) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(17, 11);
    PathTracerSettings pt{5, false};
    pt.guiding.enabled = true;
    pt.guiding.keep_training_samples = true;
    pt.guiding.training_passes = 3;
    pt.guiding.spatial_threshold = 300;
    RenderSettings rs;
    rs.adaptive.enabled = false;  // compared with blocks of every pixel's samples
    rs.samples_per_pixel = 5;
    rs.seed = 23;
    rs.threads = 2;
    Image expected;
    Film expected_film(camera.width(), camera.height(), true);
    if (world_rank() == 0) {
        PathTracer one(pt);
        expected = render(scene, camera, one, rs);
        PathTracer block(pt);
        block.preprocess(scene);
        (void)train(scene, camera, block, rs);
        (void)render_block(scene, camera, block, expected_film,
                           {0, 0, camera.width(), camera.height(), 0, 5}, rs.block());
        ASSERT_FALSE(same_records(expected_film, Film(camera.width(), camera.height(), true)));
    }
    for (const int tile : {4, 32}) {
        for (const int threads : {1, 2}) {
            PathTracer tracer(pt);
            MpiRenderSettings s;
            s.render = rs;
            s.render.threads = threads;
            s.tile_size = tile;
            s.aovs = true;
            Image image;
            MpiRenderStats stats;
            const Film film = render_mpi(MPI_COMM_WORLD, scene, camera, tracer, s, &stats, &image);
            EXPECT_FALSE(stats.cancelled);
            if (world_rank() == 0) {
                EXPECT_TRUE(same_pixels(image, expected))
                    << "tile " << tile << ", threads " << threads;
                EXPECT_TRUE(same_records(film, expected_film))
                    << "tile " << tile << ", threads " << threads;
            } else {
                EXPECT_TRUE(image.pixels.empty());
            }
        }
    }
}

// A bad setting is found on every rank, and rank 0 names itself (the lowest failing rank).
TEST(RenderMpi, BadSettingsThrowOnEveryRank) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(8, 8);
    PathTracer integrator;
    const auto expect_error = [&](const MpiRenderSettings& s, const std::string& message) {
        try {
            (void)render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s);
            ADD_FAILURE() << "no exception: " << message;
        } catch (const Error& e) {
            const std::string text = e.what();
            if (world_rank() == 0) {
                EXPECT_NE(text.find("rank 0 failed: " + message), std::string::npos) << text;
            }
        }
    };
    MpiRenderSettings s;
    s.tile_size = 0;
    expect_error(s, "tile_size = 0");
    s = {};
    s.render.adaptive.enabled = true;
    s.render.adaptive.radius = -1;  // 0 is automatic
    expect_error(s, "adaptive.radius = -1");
}

// Ranks given different jobs fail on every rank before any tile, naming the rank and what
// differs. Here rank 1 on splatted while rank 0 did not: rank 0 finished without its splats
// and waited in MPI_Finalize, rank 1 waited for ever to send them.
TEST(RenderMpi, RanksGivenDifferentJobsFailOnEveryRank) {
    int size = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    if (size == 1) GTEST_SKIP() << "needs ranks to compare";
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(8, 8);
    PathTracer path_tracer;
    librt::testing::RandomSplatter splatter;
    const auto message = [&](Integrator& integrator, const MpiRenderSettings& s) {
        try {
            (void)render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    MpiRenderSettings s;
    s.render.threads = 1;
    const std::string more = size == 3 ? "; 1 more rank differs" : "";
    EXPECT_EQ(message(world_rank() == 0 ? static_cast<Integrator&>(path_tracer) : splatter, s),
              "rank 1: integrator splats differs from rank 0 (yes vs no)" + more);
    MpiRenderSettings other = s;
    other.render.samples_per_pixel = 2;
    other.tile_size = 4;
    EXPECT_EQ(message(path_tracer, world_rank() == size - 1 ? other : s),
              "rank " + std::to_string(size - 1) +
                  ": tile_size differs from rank 0 (4 vs 32); also samples_per_pixel");
    // Agreeing again, the ranks render.
    const Film film = render_mpi(MPI_COMM_WORLD, scene, camera, path_tracer, s);
    if (world_rank() == 0) {
        EXPECT_EQ(uniform_sample_count(film), 1u);
    }
}

namespace {

// The path tracer whose samples on rank 0 wait until release() (called by rank 0's
// progress callback when the render has reached a point the test chooses): rank 0's own
// rendering thread cannot get past its first sample before then, however the machine
// schedules the ranks. The hold is per call: hold() before each.
class HeldOnRankZero final : public Integrator {
public:
    explicit HeldOnRankZero(const PathTracerSettings& settings = {}) : inner_(settings) {}
    void preprocess(const Scene& scene) override { inner_.preprocess(scene); }
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray,
                               Sampler& sampler) const override {
        if (world_rank() == 0) {
            std::unique_lock<std::mutex> lock(mutex_);
            released_cv_.wait(lock, [this] { return released_; });
        }
        return inner_.li(scene, ray, sampler);
    }
    void hold() {
        const std::lock_guard<std::mutex> lock(mutex_);
        released_ = false;
    }
    void release() {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            released_ = true;
        }
        released_cv_.notify_all();
    }

private:
    PathTracer inner_;
    mutable std::mutex mutex_;
    mutable std::condition_variable released_cv_;
    bool released_ = false;
};

}  // namespace

// Calls in a row (frames of an animation): a worker's first request of the next call must
// not be taken by rank 0 for the call it is still finishing (it used to be, and the next
// call then waited for a request that had already been answered "done").
TEST(RenderMpi, CallsInARowKeepTheirMessagesApart) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(8, 8);
    // Rank 0's own rendering thread holds its tile until rank 0's progress shows every
    // other tile back: the other ranks finish each call, and go on to the next, before
    // rank 0 has finished it, in every run (a sleep here only made that order likely).
    HeldOnRankZero integrator;
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    MpiRenderSettings s;
    s.render.threads = 1;
    s.tile_size = 4;  // 4 tiles: rank 0's thread holds at most one, the others do the rest
    if (world_rank() == 0) {
        s.render.progress = [&integrator, ranks](const RenderProgress& p) {
            if (ranks == 1 || p.fraction >= 3.0 / 4.0 - 1e-9) integrator.release();
        };
    }
    const auto call = [&](std::uint64_t seed) {
        integrator.hold();
        s.render.seed = seed;
        return render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s);
    };
    Film first;
    for (int c = 0; c < 3; ++c) {
        const Film film = call(static_cast<std::uint64_t>(c));
        if (world_rank() == 0) {
            EXPECT_EQ(uniform_sample_count(film), 1u) << "call " << c;
            if (c == 0) first = film;
        }
    }
    // The same settings again give the same film.
    const Film again = call(0);
    if (world_rank() == 0) {
        EXPECT_TRUE(same_records(again, first));
    }
}

// An integrator that splats: every rank's splats, summed over all its tiles, reach rank 0
// (kSplats) and add up exactly, so the film holds a one-process render_block's records and
// splat sums, and the image is render()'s, for any tile size, thread count, number of ranks
// and whether rank 0 renders.
TEST(RenderMpi, SplattingIntegratorGivesRendersImage) {
    const Scene scene = empty_scene();
    const Camera camera = librt::testing::splat_test_camera(19, 13, false);
    librt::testing::RandomSplatter integrator(splatter_options(false));
    RenderSettings rs;
    rs.adaptive.enabled = false;  // compared with blocks of every pixel's samples
    rs.samples_per_pixel = 4;
    rs.seed = 5;
    rs.threads = 2;
    Image expected;
    Film expected_film(camera.width(), camera.height());
    if (world_rank() == 0) {
        expected = render(scene, camera, integrator, rs);
        (void)render_block(scene, camera, integrator, expected_film,
                           {0, 0, camera.width(), camera.height(), 0, 4}, rs.block());
        ASSERT_TRUE(expected_film.splats.has_value());
    }
    for (const int tile : {3, 32}) {
        for (const int threads : {1, 2}) {
            for (const bool root_renders : {true, false}) {
                MpiRenderSettings s = split(rs, threads, tile, root_renders);
                s.render.tile_size = 2;
                Image image;
                MpiRenderStats stats;
                const Film film =
                    render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s, &stats, &image);
                EXPECT_FALSE(stats.cancelled);
                if (world_rank() == 0) {
                    const std::string where = "tile " + std::to_string(tile) + ", threads " +
                                              std::to_string(threads) + ", root renders " +
                                              std::to_string(root_renders);
                    EXPECT_TRUE(same_records(film, expected_film)) << where;
                    EXPECT_TRUE(same_splats(film, expected_film)) << where;
                    EXPECT_TRUE(same_pixels(image, expected)) << where;
                    EXPECT_TRUE(same_pixels(resolve(film), expected)) << where;
                } else {
                    EXPECT_TRUE(film.pixels.empty());
                }
            }
        }
    }
}

// A splatting integrator that keeps its training passes: the first halves' splats travel
// apart from the rest, so rank 0 joins the passes to the film as render() does.
TEST(RenderMpi, SplattingKeptTrainingPassesGiveRendersImage) {
    const Scene scene = empty_scene();
    const Camera camera = librt::testing::splat_test_camera(17, 11, false);
    RenderSettings rs;
    rs.adaptive.enabled = false;  // compared with blocks of every pixel's samples
    rs.samples_per_pixel = 5;
    rs.seed = 9;
    rs.threads = 2;
    Image expected;
    Film expected_film(camera.width(), camera.height());
    if (world_rank() == 0) {
        librt::testing::RandomSplatter one(splatter_options(true));
        expected = render(scene, camera, one, rs);
        librt::testing::RandomSplatter block(splatter_options(true));
        block.preprocess(scene);
        (void)train(scene, camera, block, rs);
        (void)render_block(scene, camera, block, expected_film,
                           {0, 0, camera.width(), camera.height(), 0, 5}, rs.block());
        ASSERT_FALSE(same_pixels(expected, resolve(expected_film)));  // the passes show
    }
    for (const int tile : {4, 32}) {
        for (const bool root_renders : {true, false}) {
            librt::testing::RandomSplatter integrator(splatter_options(true));
            MpiRenderSettings s;
            s.render = rs;
            s.tile_size = tile;
            s.root_renders = root_renders;
            Image image;
            const Film film =
                render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s, nullptr, &image);
            if (world_rank() == 0) {
                const std::string where = "tile " + std::to_string(tile) + ", root renders " +
                                          std::to_string(root_renders);
                EXPECT_TRUE(same_pixels(image, expected)) << where;
                EXPECT_TRUE(same_records(film, expected_film)) << where;
                EXPECT_TRUE(same_splats(film, expected_film)) << where;
            }
        }
    }
}

// Adaptive sampling over the ranks: the pilots of all tiles, the counts computed on rank 0
// from the whole image, then each tile continued to its counts. The film (with its AOVs)
// and the image are render()'s adaptive ones bit for bit, for any tile size, thread count,
// sampler, number of ranks and whether rank 0 renders.
TEST(RenderMpi, AdaptiveSamplingGivesRendersFilm) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(23, 14);
    const PathTracerSettings pt{4, false};
    for (const SamplerKind kind : {SamplerKind::Independent, SamplerKind::Sobol}) {
        RenderSettings rs;
        rs.samples_per_pixel = 12;  // pilot 2
        rs.seed = 7;
        rs.threads = 2;
        rs.sampler = kind;
        rs.adaptive.enabled = true;
        rs.adaptive.radius = 2;
        Film expected(camera.width(), camera.height(), true);
        Image expected_image;
        if (world_rank() == 0) {
            PathTracer one(pt);
            const RenderStats st = render(scene, camera, one, expected, rs);
            expected_image = resolve(expected);
            // The counts do differ, or this would test nothing adaptive.
            std::uint32_t low = ~0u, high = 0;
            for (const FilmPixel& p : expected.pixels) {
                low = std::min(low, p.samples);
                high = std::max(high, p.samples);
            }
            ASSERT_LT(low, high);
            ASSERT_LE(st.samples, 12u * expected.pixels.size());
        }
        for (const int tile : {4, 32}) {
            for (const int threads : {1, 2}) {
                for (const bool root_renders : {true, false}) {
                    PathTracer tracer(pt);
                    MpiRenderSettings s = split(rs, threads, tile, root_renders, true);
                    s.render.tile_size = 3;
                    Image image;
                    MpiRenderStats stats;
                    const Film film =
                        render_mpi(MPI_COMM_WORLD, scene, camera, tracer, s, &stats, &image);
                    EXPECT_FALSE(stats.cancelled);
                    if (world_rank() == 0) {
                        const std::string where = "sampler " + std::to_string(int(kind)) +
                                                  ", tile " + std::to_string(tile) + ", threads " +
                                                  std::to_string(threads) + ", root renders " +
                                                  std::to_string(root_renders);
                        EXPECT_TRUE(same_records(film, expected)) << where;
                        EXPECT_TRUE(same_pixels(image, expected_image)) << where;
                        // Every tile twice: its pilot, then the rest of its counts.
                        int sum = 0;
                        for (const int n : stats.tiles_per_rank) sum += n;
                        EXPECT_EQ(sum, stats.tiles) << where;
                        const int tiles_x = (camera.width() + tile - 1) / tile;
                        const int tiles_y = (camera.height() + tile - 1) / tile;
                        EXPECT_EQ(stats.tiles, 2 * tiles_x * tiles_y) << where;
                    }
                }
            }
        }
    }
}

// A splatting integrator with adaptive sampling: every splat, the pilot's and the rest's,
// sums into the film's splats, and the image is render()'s.
TEST(RenderMpi, AdaptiveSamplingWithSplatsGivesRendersImage) {
    const Scene scene = empty_scene();
    const Camera camera = librt::testing::splat_test_camera(19, 13, false);
    librt::testing::RandomSplatter integrator(splatter_options(false));
    RenderSettings rs;
    rs.samples_per_pixel = 8;  // pilot 2
    rs.seed = 3;
    rs.threads = 2;
    rs.adaptive.enabled = true;
    rs.adaptive.radius = 1;
    Film expected_film(camera.width(), camera.height());
    Image expected;
    if (world_rank() == 0) {
        (void)render(scene, camera, integrator, expected_film, rs);
        ASSERT_TRUE(expected_film.splats.has_value());
        expected = resolve(expected_film);
    }
    for (const int tile : {3, 32}) {
        MpiRenderSettings s;
        s.render = rs;
        s.tile_size = tile;
        Image image;
        MpiRenderStats stats;
        const Film film = render_mpi(MPI_COMM_WORLD, scene, camera, integrator, s, &stats, &image);
        EXPECT_FALSE(stats.cancelled);
        if (world_rank() == 0) {
            EXPECT_TRUE(same_records(film, expected_film)) << "tile " << tile;
            EXPECT_TRUE(same_splats(film, expected_film)) << "tile " << tile;
            EXPECT_TRUE(same_pixels(image, expected)) << "tile " << tile;
        }
    }
}

// Cancelled on rank 0 just after the pilots, with the rest out on the other ranks: every
// rank returns, cancelled, and no rank waits for a message that never comes (else ctest's
// TIMEOUT fails the test). Decided by events, not by speed: rank 0's own thread holds its
// first sample until its progress shows every other pilot back, so the other ranks have
// sent their last pilots and wait for the counts; once the last pilot is in, rank 0 sets
// the counts, hands out rest tiles to the waiting ranks, and reports the pilot's end, on
// which its callback cancels. Alone, rank 0's thread is released at the first report.
TEST(RenderMpi, AdaptiveSamplingCancelledAfterThePilotStopsEveryRank) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(16, 12);
    HeldOnRankZero tracer(PathTracerSettings{4, false});
    std::atomic<bool> cancel{false};
    MpiRenderSettings s;
    s.render.samples_per_pixel = 64;  // pilot 16
    s.render.seed = 2;
    s.render.threads = 1;
    s.render.adaptive.enabled = true;
    s.render.cancel = &cancel;
    s.tile_size = 4;  // 12 tiles
    constexpr int kTiles = 12;
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    int pilot_reports = 0;
    bool completed = false;
    if (world_rank() == 0) {
        // Progress weighs a pilot tile 16 / 64 of a tile: 11 of the 12 pilots are back.
        const double all_but_one_pilot = 11.0 / 12.0 * 16.0 / 64.0;
        s.render.progress = [&, ranks, all_but_one_pilot](const RenderProgress& p) {
            if (ranks == 1 || p.fraction >= all_but_one_pilot - 1e-9) tracer.release();
            if (p.samples_per_pixel == 16 && p.passes == 0) {
                ++pilot_reports;
                cancel = true;
            }
            if (p.passes > 0) completed = true;
        };
    }
    MpiRenderStats stats;
    const Film film = render_mpi(MPI_COMM_WORLD, scene, camera, tracer, s, &stats);
    EXPECT_TRUE(stats.cancelled);
    if (world_rank() == 0) {
        EXPECT_EQ(pilot_reports, 1);
        EXPECT_FALSE(completed);
        // The counts were set, so every pilot was in: every pixel holds at least its pilot,
        // none past 8 x 64.
        for (const FilmPixel& p : film.pixels) {
            EXPECT_GE(p.samples, 16u);
            EXPECT_LE(p.samples, 8u * 64u);
        }
        if (ranks > 1) {
            // Rank 0's thread rendered at most one pilot tile, so the others rendered at
            // least 11, and the rank that sent the last of them was handed a rest tile
            // before the cancel: the cancel reached a rank with the rest out.
            int others = 0;
            for (std::size_t r = 1; r < stats.tiles_per_rank.size(); ++r)
                others += stats.tiles_per_rank[r];
            EXPECT_GE(others, kTiles);
        }
    }
}

// Cancelled on rank 0 while the pilots are still out: rank 0's own thread holds its first
// pilot sample until rank 0 cancels, which it does once every other pilot tile is back
// (its progress says so), so the other ranks have finished theirs and their requests wait
// for counts that cannot come. The cancel must reach those waiting requests too (each is
// answered "stop"), and no rank hangs (else ctest's TIMEOUT fails the test). Alone, rank 0
// cancels at its first report. (Should rank 0's thread get no pilot tile, it holds its
// first sample after the pilots instead and the test still ends, cancelled.)
TEST(RenderMpi, AdaptiveSamplingCancelledBeforeTheCountsStopsEveryRank) {
    const Scene scene = film_test_scene();
    const Camera camera = film_test_camera(16, 12);
    std::atomic<bool> cancel{false};
    HeldOnRankZero tracer(PathTracerSettings{4, false});
    MpiRenderSettings s;
    s.render.samples_per_pixel = 64;  // pilot 16
    s.render.seed = 4;
    s.render.threads = 1;
    s.render.adaptive.enabled = true;
    s.render.cancel = &cancel;
    s.tile_size = 4;  // 12 tiles
    int ranks = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &ranks);
    if (world_rank() == 0) {
        // Progress weighs a pilot tile 16 / 64 of a tile: 11 of the 12 pilots are back.
        const double all_but_one_pilot = 11.0 / 12.0 * 16.0 / 64.0;
        // By value: the constant's scope ends before the render calls this.
        s.render.progress = [&tracer, &cancel, ranks, all_but_one_pilot](const RenderProgress& p) {
            if (ranks == 1 || p.fraction >= all_but_one_pilot - 1e-9) {
                cancel = true;  // before the release: the released sample's render sees it
                tracer.release();
            }
        };
    }
    MpiRenderStats stats;
    const Film film = render_mpi(MPI_COMM_WORLD, scene, camera, tracer, s, &stats);
    EXPECT_TRUE(stats.cancelled);
    if (world_rank() == 0) {
        for (const FilmPixel& p : film.pixels) EXPECT_LE(p.samples, 8u * 64u);
    }
}
