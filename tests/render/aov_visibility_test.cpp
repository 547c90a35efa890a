// The visibility AOV (render/aov.h, AovSample::visibility) against a shadow whose edges are
// known in closed form: a plane lit by a sun at 45 degrees, a slab above it casting a
// band of shadow 3.1 units wide, seen by an orthographic camera of one scene unit per pixel through
// a box pixel filter. A pixel's visibility is the share of its area that sees a lit point.

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrator.h>
#include <librt/light/directional_light.h>
#include <librt/render/denoiser.h>
#include <librt/render/renderer.h>
#include <librt/sampling/filter.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace librt;

namespace {

constexpr int kWidth = 16, kHeight = 8;
constexpr std::uint32_t kSpp = 256;
/// The slab's left edge; its shadow on the plane begins 3.1 units to its left.
constexpr float kEdge = 3.3f;

/// Black radiance: the test needs only the AOVs.
class Black final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& /*ray*/,
                               Sampler& /*sampler*/) const override {
        return glm::vec3(0.0f);
    }
};

/// The plane z = -5 (a slab's top) and, unless `bare`, a slab z in [-2, -1.9] over
/// x >= kEdge; lit by a sun toward (1, 0, 1) unless `dark`. The film of the first `part`
/// samples in `first` when given.
ImageLayers render(bool dark, bool bare, Film* first = nullptr, std::uint32_t part = 0,
                   Film* full = nullptr) {
    Scene scene;
    const std::uint32_t grey = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    (void)scene.add_mesh(make_box({-50.0f, -50.0f, -6.0f}, {50.0f, 50.0f, -5.0f}), grey);
    if (!bare) (void)scene.add_mesh(make_box({kEdge, -50.0f, -2.0f}, {50.0f, 50.0f, -1.9f}), grey);
    if (!dark) {
        DirectionalLight sun;
        sun.to_light = {1.0f, 0.0f, 1.0f};
        sun.irradiance = glm::vec3(1.0f);
        (void)scene.add_directional_light(sun);
    }
    scene.commit();
    CameraSettings cs;
    cs.position = {0.0f, 0.0f, 0.0f};
    cs.look_at = {0.0f, 0.0f, -1.0f};
    cs.projection = Projection::Orthographic;
    cs.width = kWidth;
    cs.height = kHeight;
    cs.xmag = kWidth / 2.0f;  // one scene unit per pixel
    cs.ymag = kHeight / 2.0f;
    cs.pixel_jitter = PixelJitter::Filter;
    cs.pixel_filter = default_filter_settings(FilterKind::Box);
    cs.pixel_filter.radius = 0.5f;  // one pixel's square
    const Camera camera(cs);
    Black integrator;
    Film film(kWidth, kHeight, true);
    BlockSettings rs;
    rs.seed = 5;
    rs.threads = 2;
    rs.sampler = SamplerKind::Independent;  // the binomial spread below
    if (first != nullptr) {
        (void)render_block(scene, camera, integrator, film, {0, 0, kWidth, kHeight, 0, part}, rs);
        *first = film;
    }
    (void)render_block(scene, camera, integrator, film,
                       {0, 0, kWidth, kHeight, first != nullptr ? part : 0u,
                        first != nullptr ? kSpp - part : kSpp},
                       rs);
    if (full != nullptr) *full = film;
    return resolve_layers(film);
}

/// The share of [a, b] in which the plane seen straight down is lit: the sun's ray from
/// plane point x at 45 degrees meets the slab's top corner (kEdge, -1.9) when x = kEdge -
/// 3.1, so x in [kEdge - 3.1, kEdge) is shadowed, and from kEdge on the camera sees the
/// slab's top, which the sun lights.
double lit_share(double a, double b) {
    const double s0 = kEdge - 3.1, s1 = kEdge;
    const double shadow = std::max(0.0, std::min(b, s1) - std::max(a, s0));
    return 1.0 - shadow / (b - a);
}

}  // namespace

TEST(AovVisibility, ShadowBandMatchesItsClosedForm) {
    const ImageLayers layers = render(false, false);
    ASSERT_EQ(layers.visibility.size(), std::size_t(kWidth * kHeight));
    bool straddled = false, shadowed = false, lit = false;
    for (int x = 0; x < kWidth; ++x) {
        const double left = x - kWidth / 2.0;
        const double f = lit_share(left, left + 1.0);
        double s = 0.0;
        for (int y = 0; y < kHeight; ++y) {
            const float v = layers.visibility[std::size_t(y * kWidth + x)];
            // A pixel wholly lit or wholly shadowed: every sample says so (a delta light).
            if (f == 0.0 || f == 1.0) {
                EXPECT_EQ(v, float(f)) << "pixel " << x << ", " << y;
            }
            s += v;
        }
        shadowed = shadowed || f == 0.0;
        lit = lit || f == 1.0;
        if (f == 0.0 || f == 1.0) continue;
        straddled = true;
        // Across the edge: the mean of kHeight x kSpp independent samples of a Bernoulli(f)
        // (the box filter's offsets are uniform over the pixel); 5 standard errors.
        const double se = std::sqrt(f * (1.0 - f) / double(kHeight * kSpp));
        EXPECT_NEAR(s / kHeight, f, 5.0 * se) << "column " << x;
    }
    // The band and both its edges are in the frame (0.2 and 0.7 of a pixel lit).
    EXPECT_TRUE(straddled && shadowed && lit);
}

// Nothing to shadow: no lights, or no occluder, gives 1 everywhere.
TEST(AovVisibility, OneWithoutLightsOrOccluders) {
    for (const bool dark : {true, false}) {
        const ImageLayers layers = render(dark, !dark);
        for (const float v : layers.visibility) ASSERT_EQ(v, 1.0f) << (dark ? "no light" : "bare");
    }
}

// The denoiser's halves (denoiser_input): the first part's visibility as its film resolves
// it, the rest's from the difference of the sums, the two making up the whole in
// proportion to their samples.
TEST(AovVisibility, DenoiserInputSplitsItIntoHalves) {
    Film first, full;
    const ImageLayers layers = render(false, false, &first, 96, &full);
    const DenoiserInput in = denoiser_input(first, full);
    const ImageLayers first_layers = resolve_layers(first);
    for (std::size_t i = 0; i < layers.visibility.size(); ++i) {
        EXPECT_EQ(in.visibility_a.pixels[i], glm::vec3(first_layers.visibility[i]));
        const float s = in.share_a[i];
        const float whole =
            s * in.visibility_a.pixels[i].x + (1.0f - s) * in.visibility_b.pixels[i].x;
        EXPECT_NEAR(whole, layers.visibility[i], 1e-6f) << "pixel " << i;
    }
}
