// The AOV layers under a pixel filter with negative lobes (Mitchell-Netravali): the albedo
// is the filtered mean sum(w a) / sum(w), so a constant albedo comes out exactly and an
// albedo step edge gives the normalised filter's integral; depth stays the mean over
// samples drawn from |f|, within the depths the pixel sees. Closed forms from the
// Mitchell-Netravali cubic written out here (Mitchell and Netravali 1988, eq. 8), not from
// librt's filter.

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/geometry/procedural.h>
#include <librt/integrator/integrator.h>
#include <librt/render/renderer.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

using namespace librt;

namespace {

constexpr double kB = 1.0 / 3.0, kC = 1.0 / 3.0;  // the default Mitchell filter (radius 2)

/// Mitchell-Netravali cubic k(x) on [-2, 2] (Mitchell and Netravali 1988, eq. 8).
double mitchell(double x) {
    const double a = std::fabs(x);
    if (a < 1.0)
        return ((12.0 - 9.0 * kB - 6.0 * kC) * a * a * a + (-18.0 + 12.0 * kB + 6.0 * kC) * a * a +
                (6.0 - 2.0 * kB)) /
               6.0;
    if (a < 2.0)
        return ((-kB - 6.0 * kC) * a * a * a + (6.0 * kB + 30.0 * kC) * a * a +
                (-12.0 * kB - 48.0 * kC) * a + (8.0 * kB + 24.0 * kC)) /
               6.0;
    return 0.0;
}

/// Integral of g over [-2, t] by the composite Simpson rule on 20000 intervals (g is a
/// piecewise cubic: exact up to rounding).
double integral_to(const std::function<double(double)>& g, double t) {
    t = std::clamp(t, -2.0, 2.0);
    const int n = 20000;
    const double h = (t + 2.0) / n;
    double s = g(-2.0) + g(t);
    for (int i = 1; i < n; ++i) s += (i % 2 == 1 ? 4.0 : 2.0) * g(-2.0 + i * h);
    return s * h / 3.0;
}

/// Black radiance: the test needs only the AOVs.
class Black final : public Integrator {
public:
    [[nodiscard]] glm::vec3 li(const Scene& /*scene*/, const Ray& /*ray*/,
                               Sampler& /*sampler*/) const override {
        return glm::vec3(0.0f);
    }
};

}  // namespace

// Two diffuse slabs meet at x = kEdge: albedo a1 and depth 5 to the left, a2 and depth 7
// to the right, seen by an orthographic camera of one scene unit per pixel. A pixel whose
// centre is at x_c sees the left slab with the filter's weight fraction
// G(kEdge - x_c) = integral of f up to kEdge - x_c / integral of f, so its albedo tends to
// a2 + (a1 - a2) G; depth uses |f| instead (G_abs), the mean over where samples land. Each
// column's 32 rows are independent replicates: the column's mean is checked to 5 standard
// errors (from the rows' spread) plus a bound on the ratio estimator's O(1/n) bias.
TEST(AovFilter, MitchellAlbedoIsTheFilteredMeanAndDepthTheAbsMean) {
    constexpr float kEdge = 0.3f;
    constexpr int kWidth = 16, kHeight = 32;
    constexpr std::uint32_t kSpp = 1024;
    const glm::vec3 a1(0.9f, 0.5f, 0.1f), a2(0.1f, 0.2f, 0.7f);
    Scene scene;
    (void)scene.add_mesh(make_box({-50.0f, -50.0f, -6.0f}, {kEdge, 50.0f, -5.0f}),
                         scene.add_material(Material::diffuse(a1)));
    (void)scene.add_mesh(make_box({kEdge, -50.0f, -8.0f}, {50.0f, 50.0f, -7.0f}),
                         scene.add_material(Material::diffuse(a2)));
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
    cs.pixel_filter = default_filter_settings(FilterKind::Mitchell);
    ASSERT_EQ(cs.pixel_filter.radius, 2.0f);
    const Camera camera(cs);
    Black integrator;
    Film film(kWidth, kHeight, true);
    BlockSettings rs;
    rs.seed = 3;
    rs.threads = 2;
    rs.sampler = SamplerKind::Independent;  // the spread over rows below: independent pixels
    (void)render_block(scene, camera, integrator, film, {0, 0, kWidth, kHeight, 0, kSpp}, rs);
    const ImageLayers layers = resolve_layers(film);

    const double total = integral_to(mitchell, 2.0);
    const auto abs_f = [](double x) { return std::fabs(mitchell(x)); };
    const double total_abs = integral_to(abs_f, 2.0);
    // E[sign] of a 2D sample = (integral f / integral |f|)^2; the ratio estimator's bias is
    // about Var(sum of signs / n) / E[sign]^2 times the albedo's range, bounded here by 3x.
    const double mean_sign = (total / total_abs) * (total / total_abs);
    const double bias = 3.0 * (1.0 - mean_sign * mean_sign) / (kSpp * mean_sign * mean_sign);

    std::uint32_t negative = 0;
    for (const AovPixel& a : film.aovs) negative += a.negative;
    // About 1 - mean_sign of the samples over 2 are negative: the lobes were sampled.
    EXPECT_GT(negative, std::uint32_t(0.25 * (1.0 - mean_sign) * kWidth * kHeight * kSpp));

    bool resolved_sign = false;  // some column tells the signed mean from the |f| mean
    for (int x = 0; x < kWidth; ++x) {
        const double centre = x - kWidth / 2.0 + 0.5;
        const double t = kEdge - centre;
        const double g = integral_to(mitchell, t) / total;
        const double g_abs = integral_to(abs_f, t) / total_abs;
        for (int c = 0; c < 3; ++c) {
            double s = 0.0, s2 = 0.0;
            for (int y = 0; y < kHeight; ++y) {
                const double v = layers.albedo.at(x, y)[c];
                s += v;
                s2 += v * v;
            }
            const double mean = s / kHeight;
            const double se =
                std::sqrt(std::max(0.0, s2 / kHeight - mean * mean) / (kHeight - 1.0));
            const double range = std::fabs(double(a1[c]) - double(a2[c]));
            const double expected = a2[c] + (double(a1[c]) - a2[c]) * g;
            const double tol = 5.0 * se + bias * range;
            EXPECT_NEAR(mean, expected, tol) << "column " << x << " channel " << c;
            if (std::fabs(t) > 2.0) {
                // Every sample on one slab: exactly its albedo in every pixel.
                for (int y = 0; y < kHeight; ++y)
                    EXPECT_FLOAT_EQ(layers.albedo.at(x, y)[c], t > 0.0 ? a1[c] : a2[c])
                        << "pixel " << x << ", " << y;
            }
            if (range * std::fabs(g - g_abs) > 3.0 * tol) resolved_sign = true;
        }
        // Depth: the mean over where the samples landed, 5 + 2 (1 - G_abs), in [5, 7].
        double s = 0.0, s2 = 0.0;
        for (int y = 0; y < kHeight; ++y) {
            const double d = layers.depth[std::size_t(y * kWidth + x)];
            EXPECT_GE(d, 5.0 - 1e-4);
            EXPECT_LE(d, 7.0 + 1e-4);
            EXPECT_EQ(layers.normal.at(x, y), glm::vec3(0.0f, 0.0f, 1.0f));
            s += d;
            s2 += d * d;
        }
        const double mean = s / kHeight;
        const double se = std::sqrt(std::max(0.0, s2 / kHeight - mean * mean) / (kHeight - 1.0));
        EXPECT_NEAR(mean, 5.0 + 2.0 * (1.0 - g_abs), 5.0 * se + 1e-5) << "column " << x;
    }
    EXPECT_TRUE(resolved_sign) << "the test cannot tell the signed mean from the |f| mean";
}

// Without negative lobes (a tent) nothing changes: no negative samples, and the albedo is
// the plain mean of the samples.
TEST(AovFilter, NonNegativeFiltersKeepThePlainMean) {
    Scene scene;
    (void)scene.add_mesh(make_box({-50.0f, -50.0f, -6.0f}, {0.3f, 50.0f, -5.0f}),
                         scene.add_material(Material::diffuse(glm::vec3(0.8f))));
    scene.commit();
    CameraSettings cs;
    cs.position = {0.0f, 0.0f, 0.0f};
    cs.look_at = {0.0f, 0.0f, -1.0f};
    cs.projection = Projection::Orthographic;
    cs.width = cs.height = 8;
    cs.xmag = cs.ymag = 4.0f;
    cs.pixel_jitter = PixelJitter::Filter;
    cs.pixel_filter = default_filter_settings(FilterKind::Tent);
    Black integrator;
    Film film(8, 8, true);
    (void)render_block(scene, Camera(cs), integrator, film, {0, 0, 8, 8, 0, 16}, BlockSettings{});
    const ImageLayers layers = resolve_layers(film);
    for (std::size_t i = 0; i < film.aovs.size(); ++i) {
        EXPECT_EQ(film.aovs[i].negative, 0u);
        EXPECT_EQ(layers.albedo.pixels[i], glm::vec3(film.aovs[i].albedo / 16.0));
    }
}
