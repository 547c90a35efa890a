// Time-limited and interruptible rendering in passes. No test depends on wall-clock time:
// time comes from a fake clock driven by the progress callback, cancellation from a flag
// that callback sets, and a pass that must still be running at a report is held by its
// integrator until the report releases it.

#include "render/film_test_util.h"

#include <librt/core/error.h>
#include <librt/render/renderer.h>

#include <gtest/gtest.h>

#include <atomic>
#include <condition_variable>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <string>

using namespace librt;
using librt::testing::film_test_camera;
using librt::testing::film_test_scene;
using librt::testing::same_records;

namespace {

// Fast, until hold() makes every sample wait for release(): a pass then cannot end before
// the test's progress callback, which the renderer calls while the pass runs (about ten
// times a second), releases it. Which report comes mid-pass is thus fixed, not a matter of
// how long a pass takes on a loaded machine.
class Gated final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& /*ray*/,
                               Sampler& sampler) const override {
        std::unique_lock<std::mutex> lock(mutex_);
        released_.wait(lock, [this] { return !held_; });
        return glm::vec3(sampler.next_1d());
    }
    void hold() {
        const std::lock_guard<std::mutex> lock(mutex_);
        held_ = true;
    }
    void release() {
        {
            const std::lock_guard<std::mutex> lock(mutex_);
            held_ = false;
        }
        released_.notify_all();
    }

private:
    mutable std::mutex mutex_;
    mutable std::condition_variable released_;
    bool held_ = false;
};

BlockSettings seeded(std::uint64_t seed) {
    BlockSettings s;
    s.seed = seed;
    return s;
}

ProgressiveSettings progressive(int total, int pass) {
    ProgressiveSettings s;
    s.render.samples_per_pixel = total;
    s.render.threads = 2;
    s.render.seed = 99;
    s.render.tile_size = 8;
    s.render.adaptive.enabled = false;  // every pixel the same samples, as the blocks below
    s.pass_samples = pass;
    return s;
}

class ProgressiveTest : public ::testing::Test {
protected:
    ProgressiveTest() : scene_(film_test_scene()), camera_(film_test_camera()) {}

    Film one_shot(std::uint32_t spp, bool aovs) {
        integrator_.preprocess(scene_);
        Film film(camera_.width(), camera_.height(), aovs);
        BlockSettings s;
        s.seed = 99;
        (void)render_block(scene_, camera_, integrator_, film,
                           {0, 0, film.width, film.height, 0, spp}, s);
        return film;
    }

    Scene scene_;
    Camera camera_;
    librt::testing::WideRangeIntegrator integrator_;
};

}  // namespace

TEST_F(ProgressiveTest, PassesToASampleCountEqualTheOneShotFilm) {
    ProgressiveSettings s = progressive(11, 3);
    s.aovs = true;
    int reports_at_pass_end = 0;
    int last_passes = 0;
    s.render.progress = [&](const RenderProgress& p) {
        EXPECT_GE(p.fraction, 0.0);
        EXPECT_LE(p.fraction, 1.0);
        if (p.passes > last_passes) {
            ++reports_at_pass_end;
            EXPECT_EQ(p.samples_per_pixel,
                      std::min(11u, 3u * static_cast<std::uint32_t>(p.passes)));
        }
        last_passes = p.passes;
    };
    Film film;
    const RenderStats stats = render_progressive(scene_, camera_, integrator_, film, s);
    EXPECT_EQ(stats.passes, 4);  // 3 + 3 + 3 + 2
    EXPECT_EQ(stats.samples_per_pixel, 11u);
    EXPECT_FALSE(stats.cancelled);
    EXPECT_FALSE(stats.time_limit_reached);
    EXPECT_EQ(stats.samples, 11u * 29u * 19u);
    EXPECT_EQ(reports_at_pass_end, 4);
    EXPECT_TRUE(film.has_aovs());
    EXPECT_TRUE(same_records(film, one_shot(11, true)));
}

TEST_F(ProgressiveTest, ResumingAFilmEqualsRenderingAtOnce) {
    ProgressiveSettings s = progressive(4, 1);
    Film film;
    (void)render_progressive(scene_, camera_, integrator_, film, s);
    EXPECT_EQ(uniform_sample_count(film), 4u);
    s.render.samples_per_pixel = 9;
    s.pass_samples = 2;
    const RenderStats more = render_progressive(scene_, camera_, integrator_, film, s);
    EXPECT_EQ(more.passes, 3);  // 4 -> 6 -> 8 -> 9
    EXPECT_EQ(more.samples_per_pixel, 9u);
    EXPECT_TRUE(same_records(film, one_shot(9, false)));
}

// The fake clock advances one second at the end of each pass: with a limit of 3.5 s the
// render must stop after the fourth pass, the first to end past the limit.
TEST_F(ProgressiveTest, TimeLimitStopsWithinOnePass) {
    ProgressiveSettings s = progressive(1000, 2);
    s.time_limit = 3.5;
    double now = 100.0;
    s.clock = [&now] { return now; };
    int seen_passes = 0;
    s.render.progress = [&](const RenderProgress& p) {
        if (p.passes > seen_passes) {
            seen_passes = p.passes;
            now += 1.0;
        }
    };
    Film film;
    const RenderStats stats = render_progressive(scene_, camera_, integrator_, film, s);
    EXPECT_TRUE(stats.time_limit_reached);
    EXPECT_FALSE(stats.cancelled);
    EXPECT_EQ(stats.passes, 4);
    EXPECT_EQ(stats.samples_per_pixel, 8u);
    EXPECT_EQ(stats.seconds, 4.0);
    EXPECT_TRUE(same_records(film, one_shot(8, false)));
}

// The third pass is held at its first samples, and the clock jumps past the limit at its
// first progress report; the next report releases it: that pass is abandoned and the film
// holds the two finished passes only.
TEST(Progressive, APassRunningAtTheTimeLimitIsDropped) {
    Scene scene;
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 48;
    const Camera camera(cs);
    Gated integrator;
    ProgressiveSettings s = progressive(100, 1);
    s.time_limit = 10.0;
    double now = 0.0;
    s.clock = [&now] { return now; };
    int reports_after_second_pass = 0;
    s.render.progress = [&](const RenderProgress& p) {
        if (p.passes != 2) return;
        ++reports_after_second_pass;
        if (reports_after_second_pass == 1) integrator.hold();     // the end of pass 2
        if (reports_after_second_pass == 2) now = 50.0;            // within pass 3
        if (reports_after_second_pass == 3) integrator.release();  // the limit was seen
    };
    Film film;
    const RenderStats stats = render_progressive(scene, camera, integrator, film, s);
    EXPECT_TRUE(stats.time_limit_reached);
    EXPECT_EQ(stats.passes, 2);
    EXPECT_EQ(stats.samples_per_pixel, 2u);
    EXPECT_EQ(uniform_sample_count(film), 2u);  // whole passes only
    // Pass 3 stopped at the next pixel of each of the two threads.
    EXPECT_GE(stats.samples, 2u * 48u * 48u);
    EXPECT_LE(stats.samples, 2u * 48u * 48u + 2u);
    // Exactly the first two samples of every pixel.
    Film reference(48, 48);
    (void)render_block(scene, camera, integrator, reference, {0, 0, 48, 48, 0, 2}, seeded(99));
    EXPECT_TRUE(same_records(film, reference));
}

// Cancelled by the progress callback in the middle of the (held) fourth pass: the film of
// the three finished passes comes back, each pixel the mean of 3 samples.
TEST(Progressive, CancellationReturnsTheFinishedPassesOnly) {
    Scene scene;
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 48;
    const Camera camera(cs);
    Gated integrator;
    std::atomic<bool> cancel{false};
    ProgressiveSettings s = progressive(100, 1);
    s.render.cancel = &cancel;
    int reports_after_third_pass = 0;
    s.render.progress = [&](const RenderProgress& p) {
        if (p.passes != 3) return;
        ++reports_after_third_pass;
        if (reports_after_third_pass == 1) integrator.hold();  // the end of pass 3
        if (reports_after_third_pass == 2) {                   // within pass 4
            cancel = true;
            integrator.release();
        }
    };
    Film film;
    const RenderStats stats = render_progressive(scene, camera, integrator, film, s);
    EXPECT_TRUE(stats.cancelled);
    EXPECT_FALSE(stats.time_limit_reached);
    EXPECT_EQ(stats.passes, 3);
    EXPECT_EQ(stats.samples_per_pixel, 3u);
    EXPECT_EQ(uniform_sample_count(film), 3u);
    EXPECT_LE(stats.samples, 3u * 48u * 48u + 2u);  // pass 4 stopped at the next pixels
    Film reference(48, 48);
    (void)render_block(scene, camera, integrator, reference, {0, 0, 48, 48, 0, 3}, seeded(99));
    EXPECT_TRUE(same_records(film, reference));
    const Image image = resolve(film);
    EXPECT_GT(image.at(10, 10).x, 0.0f);

    // Cancelled before the first pass: nothing rendered, the film holds no samples.
    s.render.progress = nullptr;
    Film empty;
    const RenderStats none = render_progressive(scene, camera, integrator, empty, s);
    EXPECT_TRUE(none.cancelled);
    EXPECT_EQ(none.passes, 0);
    EXPECT_EQ(none.samples, 0u);
    EXPECT_EQ(uniform_sample_count(empty), 0u);
}

// However short the limit, a film gets at least one whole pass.
TEST_F(ProgressiveTest, TheFirstPassAlwaysCompletes) {
    ProgressiveSettings s = progressive(50, 2);
    s.time_limit = 1e-9;
    double now = 0.0;
    s.clock = [&now] { return now += 1.0; };  // past the limit at every reading
    Film film;
    const RenderStats stats = render_progressive(scene_, camera_, integrator_, film, s);
    EXPECT_TRUE(stats.time_limit_reached);
    EXPECT_EQ(stats.passes, 1);
    EXPECT_EQ(uniform_sample_count(film), 2u);
}

TEST_F(ProgressiveTest, BadSettingsNameTheParameter) {
    const auto expect_error = [&](ProgressiveSettings s, Film film, const std::string& text) {
        try {
            (void)render_progressive(scene_, camera_, integrator_, film, s);
            ADD_FAILURE() << text;
        } catch (const Error& e) {
            EXPECT_NE(std::string(e.what()).find(text), std::string::npos) << e.what();
        }
    };
    ProgressiveSettings s = progressive(4, 1);
    s.pass_samples = 0;
    expect_error(s, Film{}, "pass_samples = 0");
    s = progressive(4, 1);
    s.time_limit = -1.0;
    expect_error(s, Film{}, "time_limit = -1");
    s.time_limit = std::numeric_limits<double>::quiet_NaN();
    expect_error(s, Film{}, "time_limit = nan");
    s = progressive(0, 1);
    expect_error(s, Film{}, "samples_per_pixel = 0");
    expect_error(progressive(4, 1), Film(3, 3), "film size 3 x 3");
    Film uneven(camera_.width(), camera_.height());
    uneven.at(5, 6).samples = 1;
    expect_error(progressive(4, 1), uneven, "film pixel (5, 6) holds 1 samples");
}

// A progress callback that throws mid-pass stops the workers; the exception comes out of
// render_progressive and the film keeps only what it held before (here: nothing).
TEST(Progressive, AThrowingProgressCallbackStopsTheRender) {
    Scene scene;
    scene.commit();
    CameraSettings cs;
    cs.width = cs.height = 48;
    const Camera camera(cs);
    Gated integrator;
    integrator.hold();  // the first pass cannot end before the callback has been called
    ProgressiveSettings s = progressive(4, 1);
    s.render.progress = [&](const RenderProgress&) {
        integrator.release();
        throw std::runtime_error("display gone");
    };
    Film film;
    EXPECT_THROW((void)render_progressive(scene, camera, integrator, film, s), std::runtime_error);
    EXPECT_EQ(uniform_sample_count(film), 0u);
}
