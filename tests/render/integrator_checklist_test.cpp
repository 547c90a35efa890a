// The checklist for a new integrator (docs/architecture.md, "Adding an integrator")
// followed for a minimal one, from the public API alone, and rendered through the
// renderer; and the brute-force tracer refusing the PathTracer settings it cannot honour.

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/geometry/ray_offset.h>
#include <librt/integrator/integrators.h>
#include <librt/material/bsdf.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <string>

namespace librt {
namespace {

// Step 1: a settings struct with defaults, every field checked by the constructor.
struct BsdfWalkSettings {
    int max_depth = 5;  ///< scattering events per path, in [0, 100]
};

// Step 2: a GuardedIntegrator (non-finite estimates become 0, counted) whose li() is
// const and thread-safe; step 3: random numbers by SampleDimensions, one bounce's block
// each; step 4: the BSDF and the scene asked through their seams (shade, lobes, sample),
// never by kind; step 5: preprocess() takes what it needs from the scene.
// The integrator: BSDF sampling only, emission counted where a path finds it.
class BsdfWalk final : public GuardedIntegrator {
public:
    explicit BsdfWalk(const BsdfWalkSettings& settings) : settings_(settings) {
        if (settings.max_depth < 0 || settings.max_depth > 100)
            throw Error("max_depth = " + std::to_string(settings.max_depth) +
                        ": must be in [0, 100]");
    }
    void preprocess(const Scene& scene) override {
        ++preprocess_calls;
        scene_seen_ = &scene;
    }
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& camera_ray,
                               Sampler& sampler) const override {
        li_calls.fetch_add(1, std::memory_order_relaxed);
        // Not preprocessed for this scene: a bug the guard counts (NaN becomes 0).
        if (scene_seen_ != &scene) return guard(glm::vec3(std::nanf("")));
        glm::vec3 radiance(0.0f), beta(1.0f);
        Ray ray = camera_ray;
        ray.direction = glm::normalize(ray.direction);
        for (int depth = 0;; ++depth) {
            Hit hit;
            if (!scene.intersect(ray, hit)) break;
            ShadedMaterial shaded;
            const Material& m = scene.shade(hit, ray.direction, shaded);
            radiance += beta * m.emission;
            if (depth >= settings_.max_depth || lobes(m) == BsdfLobe::None) break;
            const ShadingPoint point{
                ShadingFrame::at(hit.shading_normal, hit.geometric_normal, ray.direction),
                m.albedo};
            const std::uint32_t dim = SampleDimensions::bounce(static_cast<std::uint32_t>(depth));
            sampler.set_dimension(dim + SampleDimensions::kBounceLobe);
            const float uc = sampler.next_1d();
            sampler.set_dimension(dim + SampleDimensions::kBounceBsdf);
            const glm::vec2 u = sampler.next_2d();
            const BsdfSample bs = sample(m, point, point.frame.to_local(-ray.direction), uc, u);
            if (!bs.valid()) break;
            beta *= bs.weight;
            ray = spawn_ray(hit, point.frame.to_world(bs.wi));
        }
        return guard(radiance);
    }

    int preprocess_calls = 0;
    mutable std::atomic<int> li_calls{0};

private:
    BsdfWalkSettings settings_;
    const Scene* scene_seen_ = nullptr;
};

TEST(IntegratorChecklist, ConstructorRefusesBadSettingsByName) {
    try {
        BsdfWalk walk({-1});
        FAIL() << "max_depth = -1 accepted";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("max_depth = -1"), std::string::npos) << e.what();
    }
}

// White furnace (as Integrators.WhiteFurnace): inside a closed sphere of albedo a emitting
// Le, every path of D bounces carries Le (1 - a^(D+1)) / (1 - a) exactly, so the image
// through render() is that value in every pixel: the renderer called preprocess() once,
// then li() once per sample, and averaged what it returned.
TEST(IntegratorChecklist, MinimalIntegratorRendersTheFurnaceThroughTheRenderer) {
    Scene scene;
    const float a = 0.5f, le = 1.0f;
    Material m = Material::diffuse(glm::vec3(a));
    m.emission = glm::vec3(le);
    scene.add_sphere({{0, 0, 0}, 1.0f}, scene.add_material(m));
    scene.commit();
    CameraSettings cs;
    cs.position = {0.1f, -0.2f, 0.3f};
    cs.look_at = {0.0f, 0.0f, -1.0f};
    cs.lens = LensModel::Pinhole;
    cs.width = 8;
    cs.height = 6;
    const Camera camera(cs);
    constexpr int kDepth = 5;
    BsdfWalk walk({kDepth});
    RenderSettings rs;
    rs.samples_per_pixel = 4;
    rs.threads = 2;
    RenderStats stats;
    const Image image = render(scene, camera, walk, rs, &stats);

    const double expected = le * (1.0 - std::pow(double(a), kDepth + 1)) / (1.0 - a);
    ASSERT_EQ(image.pixels.size(), std::size_t(8 * 6));
    for (const glm::vec3& p : image.pixels)
        for (int c = 0; c < 3; ++c) ASSERT_NEAR(p[c], expected, 1e-5 * expected);
    EXPECT_EQ(walk.preprocess_calls, 1);
    EXPECT_EQ(walk.li_calls.load(), 8 * 6 * 4);
    EXPECT_EQ(stats.samples, std::uint64_t(8 * 6 * 4));
    EXPECT_EQ(walk.nonfinite_count(), 0u);
    EXPECT_FALSE(walk.splats());  // the default: li() alone, no splat film
}

// BruteForcePathTracer samples no light: the four PathTracer-only fields would change
// nothing, so it refuses them (naming field and value) instead of ignoring them.
TEST(IntegratorChecklist, BruteForceRefusesPathTracerOnlySettings) {
    const auto refusal = [](const PathTracerSettings& s) {
        try {
            BruteForcePathTracer brute(s);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string();
    };
    PathTracerSettings no_mis;
    no_mis.mis = false;
    PathTracerSettings bounded;
    bounded.light_choice = LightChoice::Bounded;
    PathTracerSettings guided;
    guided.guiding.enabled = true;
    PathTracerSettings caustics;
    caustics.caustic_paths.enabled = true;
    EXPECT_NE(refusal(no_mis).find("mis = false"), std::string::npos) << refusal(no_mis);
    EXPECT_NE(refusal(bounded).find("light_choice = Bounded"), std::string::npos);
    EXPECT_NE(refusal(guided).find("guiding.enabled = true"), std::string::npos);
    EXPECT_NE(refusal(caustics).find("caustic_paths.enabled = true"), std::string::npos);
    // The defaults, and the fields it reads, pass; PathTracer takes all four.
    EXPECT_EQ(refusal(PathTracerSettings{}), "");
    EXPECT_EQ(refusal(PathTracerSettings{7, false, 2}), "");
    for (const PathTracerSettings& s : {no_mis, bounded, guided, caustics})
        EXPECT_NO_THROW(PathTracer{s});
}

}  // namespace
}  // namespace librt
