#include "film/camera_importance.h"

#include "sampling/sanitizer_scale.h"

#include <librt/film/camera.h>
#include <librt/film/splat_film.h>
#include <librt/sampling/filter.h>
#include <librt/sampling/jitter.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/sampler.h>

#include <gtest/gtest.h>

#include <glm/ext/vector_double3.hpp>
#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <vector>

using namespace librt;

namespace {

// A camera away from the report's frame (rotated basis, non-square image) with a lens.
CameraSettings base_settings(LensModel lens) {
    CameraSettings s;
    s.position = {1.0f, 2.0f, 3.0f};
    s.look_at = {-0.5f, 1.0f, -7.0f};
    s.up = {0.1f, 1.0f, 0.0f};
    s.width = 64;
    s.height = 48;
    s.vertical_fov_degrees = 50.0f;
    s.lens = lens;
    s.lens_radius = 0.7f;
    s.lens_sigma = 0.4f;
    s.focal_distance = 8.0f;
    return s;
}

const char* lens_name(LensModel lens) {
    switch (lens) {
        case LensModel::Pinhole:
            return "pinhole";
        case LensModel::Disk:
            return "disk";
        case LensModel::Gaussian:
            return "gaussian";
    }
    return "?";
}

// The raster position sample_ray's pixel sample lands on: (j + 0.5 + dx, i + 0.5 - dy),
// from the same first 2D sample the camera draws.
glm::dvec2 expected_raster(const Camera& camera, int j, int i, std::uint32_t s,
                           std::uint64_t seed) {
    Sampler sampler(static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i), s, seed);
    const glm::vec2 u = sampler.next_2d();
    glm::vec2 offset{0.0f};
    if (camera.settings().pixel_jitter == PixelJitter::Gaussian) {
        offset = gaussian_pixel_jitter(u, camera.settings().pixel_sigma);
    } else if (camera.settings().pixel_jitter == PixelJitter::Filter) {
        offset = PixelFilter(camera.settings().pixel_filter).sample(u).offset;
    }
    return {j + 0.5 + offset.x, i + 0.5 - offset.y};
}

// A unit direction in the cone of half-angle acos(cos_max) around `axis`, uniform in
// solid angle (density 1 / (2 pi (1 - cos_max))).
glm::dvec3 cone_direction(const Camera& camera, double cos_max, glm::vec2 u) {
    const double cos_t = 1.0 - u.x * (1.0 - cos_max);
    const double sin_t = std::sqrt(std::max(0.0, 1.0 - cos_t * cos_t));
    const double phi = 2.0 * std::numbers::pi * u.y;
    return glm::dvec3(camera.forward()) * cos_t +
           glm::dvec3(camera.right()) * (sin_t * std::cos(phi)) +
           glm::dvec3(camera.true_up()) * (sin_t * std::sin(phi));
}

}  // namespace

// sample_ray then raster_of gives back the raster position sample_ray started from, for
// every lens, over many random pixels and samples: box-filtered positions inside the
// image, and Gaussian-jittered ones that may leave it (found with a wide margin).
TEST(CameraImportance, RasterOfInvertsSampleRay) {
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk, LensModel::Gaussian}) {
        for (const PixelJitter jitter : {PixelJitter::Filter, PixelJitter::Gaussian}) {
            CameraSettings s = base_settings(lens);
            s.pixel_jitter = jitter;  // Filter: the default box of radius 0.5
            const Camera camera(s);
            const float margin = jitter == PixelJitter::Gaussian ? 8.0f : 0.0f;
            Pcg32 rng(17, 3);
            double worst = 0.0;
            for (int k = 0; k < 20000; ++k) {
                const int j = static_cast<int>(rng.next_u32() % 64u);
                const int i = static_cast<int>(rng.next_u32() % 48u);
                const std::uint32_t sample = rng.next_u32() % 1024u;
                Sampler sampler(static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i),
                                sample, 99);
                const Ray ray = camera.sample_ray(j, i, sampler).ray;
                const glm::dvec2 want = expected_raster(camera, j, i, sample, 99);
                const auto got = raster_of(camera, ray, margin);
                ASSERT_TRUE(got.has_value()) << lens_name(lens) << " pixel " << j << ", " << i;
                worst = std::max({worst, std::abs(got->x - want.x), std::abs(got->y - want.y)});
                if (jitter == PixelJitter::Filter) {
                    // The box keeps the sample in its own pixel.
                    EXPECT_EQ(static_cast<int>(std::floor(got->x)), j);
                    EXPECT_EQ(static_cast<int>(std::floor(got->y)), i);
                }
            }
            EXPECT_LT(worst, 1e-3) << lens_name(lens);
        }
    }
}

// Nothing behind the camera, off the image (unless within the margin), or for an
// orthographic camera, whose directions are a delta.
TEST(CameraImportance, RasterOfRejectsWhatTheImageCannotSee) {
    const Camera camera(base_settings(LensModel::Pinhole));
    const glm::vec3 c = camera.settings().position;
    EXPECT_FALSE(raster_of(camera, Ray{c, -camera.forward()}).has_value());
    EXPECT_FALSE(raster_of(camera, Ray{c, camera.right()}).has_value());  // cos = 0
    EXPECT_EQ(camera_importance(camera, Ray{c, -camera.forward()}), 0.0f);
    // Half a pixel past the right edge: raster x = W + 0.5.
    const float d = camera.image_plane_distance();
    const glm::vec3 past = (32.5f) * camera.right() + d * camera.forward();
    EXPECT_FALSE(raster_of(camera, Ray{c, past}).has_value());
    const auto wide = raster_of(camera, Ray{c, past}, 1.0f);
    ASSERT_TRUE(wide.has_value());
    EXPECT_NEAR(wide->x, 64.5f, 1e-3f);
    EXPECT_NEAR(wide->y, 24.0f, 1e-3f);
    // The optical axis is the image centre.
    const auto centre = raster_of(camera, Ray{c, camera.forward()});
    ASSERT_TRUE(centre.has_value());
    EXPECT_NEAR(centre->x, 32.0f, 1e-3f);
    EXPECT_NEAR(centre->y, 24.0f, 1e-3f);

    CameraSettings o;
    o.projection = Projection::Orthographic;
    const Camera ortho(o);
    const Ray axis{o.position, ortho.forward()};
    EXPECT_FALSE(raster_of(ortho, axis).has_value());
    EXPECT_EQ(camera_importance(ortho, axis), 0.0f);
    EXPECT_EQ(pdf_we(ortho, axis).dir, 0.0f);
    EXPECT_FALSE(sample_wi(ortho, glm::vec3(0.0f), {0.5f, 0.5f}).valid);
    EXPECT_TRUE(lens_is_delta(ortho));
}

// The pinhole's pdf_dir is 1 / (A cos^3) with A the image's area at unit distance, and
// We = pdf_dir / cos; computed here independently in double.
TEST(CameraImportance, PinholePdfIsTheUnitPlaneJacobian) {
    const Camera camera(base_settings(LensModel::Pinhole));
    const double tan_half = std::tan(25.0 * std::numbers::pi / 180.0);
    const double area = (2.0 * tan_half * 64.0 / 48.0) * (2.0 * tan_half);
    Pcg32 rng(5, 6);
    for (int k = 0; k < 1000; ++k) {
        const glm::dvec3 dir = cone_direction(camera, 0.8, rng.next_vec2());
        const Ray ray{camera.settings().position, glm::vec3(dir)};
        if (!raster_of(camera, ray)) continue;
        const double cos_t = glm::dot(dir, glm::dvec3(camera.forward()));
        const CameraPdf pdf = pdf_we(camera, ray);
        EXPECT_EQ(pdf.pos, 1.0f);
        const double want = 1.0 / (area * cos_t * cos_t * cos_t);
        EXPECT_NEAR(pdf.dir, want, 1e-5 * want);
        EXPECT_NEAR(camera_importance(camera, ray), want / cos_t, 1e-5 * want / cos_t);
    }
}

// For a lens of finite size pdf_dir is W H / |d raster / d omega| inverted: the density of
// the direction when the raster position is uniform over the image. Checked against a
// central finite difference of raster_of in solid angle (step 1e-3 rad: truncation
// O(1e-6); float rasters of ~0.3 pixel differences round by ~3e-5 relative), so within
// 1e-3 relative.
TEST(CameraImportance, LensPdfIsTheRasterJacobian) {
    for (const LensModel lens : {LensModel::Disk, LensModel::Gaussian}) {
        const Camera camera(base_settings(lens));
        Pcg32 rng(8, 9);
        int checked = 0;
        for (int k = 0; k < 400; ++k) {
            const glm::vec2 l = lens == LensModel::Disk
                                    ? disk_lens_jitter(rng.next_vec2(), 0.7f)
                                    : gaussian_lens_jitter(rng.next_vec2(), 0.4f);
            const glm::vec3 o =
                camera.settings().position + l.x * camera.right() + l.y * camera.true_up();
            const glm::dvec3 dir = cone_direction(camera, 0.9, rng.next_vec2());
            const Ray ray{o, glm::vec3(dir)};
            if (!raster_of(camera, ray, -3.0f)) continue;  // well inside the image
            // Two tangents of the unit sphere at dir.
            const glm::dvec3 e1 = glm::normalize(glm::cross(dir, glm::dvec3(camera.true_up())));
            const glm::dvec3 e2 = glm::cross(dir, e1);
            const double h = 1e-3;
            const auto at = [&](const glm::dvec3& v) {
                const auto r = raster_of(camera, Ray{o, glm::vec3(glm::normalize(v))}, 8.0f);
                return glm::dvec2(*r);
            };
            const glm::dvec2 dx = (at(dir + h * e1) - at(dir - h * e1)) / (2.0 * h);
            const glm::dvec2 dy = (at(dir + h * e2) - at(dir - h * e2)) / (2.0 * h);
            const double jacobian = std::abs(dx.x * dy.y - dx.y * dy.x);  // pixels per sr
            const double want = jacobian / (64.0 * 48.0);
            EXPECT_NEAR(pdf_we(camera, ray).dir, want, 1e-3 * want) << lens_name(lens);
            ++checked;
        }
        EXPECT_GT(checked, 100);
    }
}

// pdf_we.dir integrates to 1 over the directions that reach the image, and so does We cos,
// from a lens point at the centre and off it: Monte Carlo over a cone of directions that
// contains the image, tolerance 5 standard errors of the estimate.
TEST(CameraImportance, DirectionPdfIntegratesToOneOverTheImage) {
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk, LensModel::Gaussian}) {
        CameraSettings s = base_settings(lens);
        s.focal_distance = 5.0f;  // a lens offset large against it bends the image region
        const Camera camera(s);
        const glm::vec2 offset =
            lens == LensModel::Pinhole ? glm::vec2(0.0f) : glm::vec2(0.6f, -0.3f);
        const glm::vec3 o = s.position + offset.x * camera.right() + offset.y * camera.true_up();
        // The image's half diagonal is 37.9 degrees from the axis; the lens offset tilts it by
        // atan(0.67 / 5) = 7.7 degrees: a cone of 60 degrees holds it all.
        const double cos_max = 0.5;
        const double cone_pdf = 1.0 / (2.0 * std::numbers::pi * (1.0 - cos_max));
        const int n = librt::testing::scaled_samples(1 << 20);  // a tenth under a sanitizer
        Pcg32 rng(21, 22);
        double sum = 0.0, sum_sq = 0.0, sum_we = 0.0, sum_we_sq = 0.0;
        int edge_hits = 0;  // directions on the cone's boundary must miss the image
        for (int k = 0; k < n; ++k) {
            const glm::dvec3 dir = cone_direction(camera, cos_max, rng.next_vec2());
            const Ray ray{o, glm::vec3(dir)};
            const double x = pdf_we(camera, ray).dir / cone_pdf;
            const double cos_t = glm::dot(dir, glm::dvec3(camera.forward()));
            const double y = camera_importance(camera, ray) * cos_t / cone_pdf;
            sum += x;
            sum_sq += x * x;
            sum_we += y;
            sum_we_sq += y * y;
            const glm::dvec3 rim = cone_direction(camera, cos_max, {1.0f, rng.next_float()});
            if (raster_of(camera, Ray{o, glm::vec3(rim)})) ++edge_hits;
        }
        EXPECT_EQ(edge_hits, 0) << lens_name(lens);
        const double mean = sum / n, mean_we = sum_we / n;
        const double err = std::sqrt((sum_sq / n - mean * mean) / n);
        const double err_we = std::sqrt((sum_we_sq / n - mean_we * mean_we) / n);
        EXPECT_NEAR(mean, 1.0, 5.0 * err) << lens_name(lens) << " (standard error " << err << ")";
        EXPECT_NEAR(mean_we, 1.0, 5.0 * err_we) << lens_name(lens);
    }
}

// sample_wi's connection agrees with the reversed ray: the same raster position as
// raster_of, the importance of camera_importance, the lens point's pdf_we.pos, and pdf =
// pdf_pos d^2 / cos_lens (1 for the pinhole's delta), weight = We cos_lens / d^2.
TEST(CameraImportance, SampleWiAgreesWithTheReversedRay) {
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk, LensModel::Gaussian}) {
        CameraSettings s = base_settings(lens);
        s.pixel_jitter = PixelJitter::Gaussian;
        const Camera camera(s);
        Pcg32 rng(31, 32);
        int valid = 0;
        for (int k = 0; k < 5000; ++k) {
            // A scene point along a camera ray, 0.5 to 40 units from the lens.
            const int j = static_cast<int>(rng.next_u32() % 64u);
            const int i = static_cast<int>(rng.next_u32() % 48u);
            Sampler sampler(static_cast<std::uint32_t>(j), static_cast<std::uint32_t>(i), 0, 5);
            const Ray ray = camera.sample_ray(j, i, sampler).ray;
            const glm::vec3 ref = ray.origin + (0.5f + 39.5f * rng.next_float()) * ray.direction;
            const CameraWi wi = sample_wi(camera, ref, rng.next_vec2());
            if (!wi.valid) continue;
            ++valid;
            EXPECT_EQ(wi.delta, lens == LensModel::Pinhole);
            EXPECT_NEAR(glm::length(wi.wi), 1.0f, 1e-6f);
            const glm::vec3 back = ref + wi.distance * wi.wi;
            EXPECT_NEAR(glm::distance(back, wi.lens_point), 0.0f, 1e-4f);
            // The lens point lies on the lens plane.
            EXPECT_NEAR(glm::dot(wi.lens_point - s.position, camera.forward()), 0.0f, 1e-5f);
            const Ray reversed{wi.lens_point, -wi.wi};
            const auto raster = raster_of(camera, reversed);
            ASSERT_TRUE(raster.has_value());
            EXPECT_NEAR(wi.raster.x, raster->x, 1e-3f);
            EXPECT_NEAR(wi.raster.y, raster->y, 1e-3f);
            const float we = camera_importance(camera, reversed);
            EXPECT_NEAR(wi.importance, we, 1e-5f * we);
            const CameraPdf pdf = pdf_we(camera, reversed);
            EXPECT_NEAR(wi.pdf_pos, pdf.pos, 1e-5f * pdf.pos);
            const float cos_lens = glm::dot(-wi.wi, camera.forward());
            const float d2 = wi.distance * wi.distance;
            const float want_pdf = lens == LensModel::Pinhole ? 1.0f : pdf.pos * d2 / cos_lens;
            EXPECT_NEAR(wi.pdf, want_pdf, 1e-5f * want_pdf);
            const float want_weight = we * cos_lens / d2;
            EXPECT_NEAR(wi.weight, want_weight, 1e-5f * want_weight);
            if (lens != LensModel::Pinhole) {
                EXPECT_NEAR(wi.weight, wi.importance * wi.pdf_pos / wi.pdf, 1e-5f * want_weight);
            }
        }
        EXPECT_GT(valid, 2500) << lens_name(lens);
    }
}

// sample_wi sees a point exactly when the camera ray through it does: along camera rays
// of every kind of lens, a point just past t_min (and before t_max) connects, one just
// before t_min (or past t_max) does not, in both near clip modes; the join ends at the
// camera ray's own t_min.
TEST(CameraImportance, SampleWiAppliesTheCameraRaysClipForEveryNearClipMode) {
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk, LensModel::Gaussian}) {
        for (const NearClipMode mode : {NearClipMode::Plane, NearClipMode::Distance}) {
            CameraSettings s = base_settings(lens);
            s.near_clip = 2.0f;
            s.near_clip_mode = mode;
            s.far_clip = 20.0f;
            const Camera camera(s);
            int checked = 0;
            for (int k = 0; k < 300; ++k) {
                const int x = (k * 7) % 64, y = (k * 5) % 48;
                Sampler sampler(std::uint32_t(x), std::uint32_t(y), std::uint32_t(k), 9);
                const Ray ray = camera.sample_ray(x, y, sampler).ray;
                // The lens sample the camera drew: its second 2D sample.
                Sampler again(std::uint32_t(x), std::uint32_t(y), std::uint32_t(k), 9);
                (void)again.next_2d();
                const glm::vec2 u_lens = again.next_2d();
                const std::string what = std::string(lens_name(lens)) +
                                         (mode == NearClipMode::Distance ? " distance" : " plane");
                const CameraWi inside = sample_wi(camera, ray.at(ray.t_min * 1.01f), u_lens);
                ASSERT_TRUE(inside.valid) << what << " k " << k;
                EXPECT_NEAR(glm::distance(inside.view_start, ray.at(ray.t_min)), 0.0f, 2e-4f)
                    << what;
                if (mode == NearClipMode::Distance) {
                    EXPECT_NEAR(glm::distance(inside.view_start, inside.lens_point), 2.0f, 1e-5f);
                }
                EXPECT_FALSE(sample_wi(camera, ray.at(ray.t_min * 0.99f), u_lens).valid) << what;
                EXPECT_TRUE(sample_wi(camera, ray.at(ray.t_max * 0.99f), u_lens).valid) << what;
                EXPECT_FALSE(sample_wi(camera, ray.at(ray.t_max * 1.01f), u_lens).valid) << what;
                ++checked;
            }
            EXPECT_EQ(checked, 300);
        }
    }
    // Off the axis the two modes disagree about the same point, as the camera rays do: a
    // point at distance 2.1 and 30 degrees off the view axis (depth 1.82) is seen only by
    // a distance clip of 2.
    CameraSettings s = base_settings(LensModel::Pinhole);
    s.near_clip = 2.0f;
    const glm::dvec3 dir =
        cone_direction(Camera(s), std::cos(std::numbers::pi / 6.0), {1.0f, 0.1f});
    const glm::vec3 point = s.position + 2.1f * glm::vec3(dir);
    EXPECT_FALSE(sample_wi(Camera(s), point, {0.5f, 0.5f}).valid);
    s.near_clip_mode = NearClipMode::Distance;
    EXPECT_TRUE(sample_wi(Camera(s), point, {0.5f, 0.5f}).valid);
}

// A point on the in-focus sphere is sharp: every lens point sees it at one raster position,
// the one whose pinhole ray reaches it. Points behind the lens plane or outside the clip
// planes connect to nothing.
TEST(CameraImportance, SampleWiSeesInFocusPointsSharpAndRespectsClipPlanes) {
    for (const LensModel lens : {LensModel::Disk, LensModel::Gaussian}) {
        CameraSettings s = base_settings(lens);
        s.near_clip = 1.0f;
        s.far_clip = 30.0f;
        const Camera camera(s);
        Pcg32 rng(41, 42);
        for (int k = 0; k < 200; ++k) {
            Sampler sampler(static_cast<std::uint32_t>(k % 64), static_cast<std::uint32_t>(k % 48),
                            0, 1);
            const glm::dvec2 want = expected_raster(camera, k % 64, k % 48, 0, 1);
            const Ray pinhole =
                Camera(base_settings(LensModel::Pinhole)).sample_ray(k % 64, k % 48, sampler).ray;
            const glm::vec3 focus = s.position + s.focal_distance * pinhole.direction;
            const CameraWi wi = sample_wi(camera, focus, rng.next_vec2());
            ASSERT_TRUE(wi.valid);
            EXPECT_NEAR(wi.raster.x, want.x, 1e-3);
            EXPECT_NEAR(wi.raster.y, want.y, 1e-3);
            // The join ends where the camera ray starts: on the segment to the lens, at
            // the near clip plane's depth.
            const glm::vec3 start = wi.view_start - wi.lens_point;
            EXPECT_NEAR(glm::dot(start, camera.forward()), s.near_clip, 1e-4f);
            EXPECT_NEAR(glm::length(glm::cross(start, wi.wi)), 0.0f, 1e-4f);
            EXPECT_LT(glm::dot(start, wi.wi), 0.0f);  // toward the point, not behind the lens
        }
        // Without a near clip plane it is the lens point itself.
        CameraSettings unclipped = s;
        unclipped.near_clip = 0.0f;
        const CameraWi open =
            sample_wi(Camera(unclipped), s.position + 5.0f * camera.forward(), {0.3f, 0.3f});
        ASSERT_TRUE(open.valid);
        EXPECT_EQ(open.view_start, open.lens_point);
        const glm::vec3 f = camera.forward();
        EXPECT_FALSE(sample_wi(camera, s.position - 5.0f * f, {0.3f, 0.3f}).valid);   // behind
        EXPECT_FALSE(sample_wi(camera, s.position + 0.5f * f, {0.3f, 0.3f}).valid);   // near
        EXPECT_FALSE(sample_wi(camera, s.position + 31.0f * f, {0.3f, 0.3f}).valid);  // far
        EXPECT_TRUE(sample_wi(camera, s.position + 20.0f * f, {0.3f, 0.3f}).valid);
    }
}

TEST(CameraImportance, SplatFilterFollowsThePixelJitter) {
    CameraSettings s;
    EXPECT_EQ(splat_filter_settings(Camera(s)).kind, FilterKind::Box);
    EXPECT_EQ(splat_filter_settings(Camera(s)).radius, 0.5f);
    s.pixel_jitter = PixelJitter::Gaussian;
    s.pixel_sigma = 0.7f;
    const FilterSettings g = splat_filter_settings(Camera(s));
    EXPECT_EQ(g.kind, FilterKind::Gaussian);
    EXPECT_EQ(g.sigma, 0.7f);
    EXPECT_TRUE(std::isinf(g.radius));
    s.pixel_jitter = PixelJitter::Filter;
    s.pixel_filter = default_filter_settings(FilterKind::Tent);
    EXPECT_EQ(splat_filter_settings(Camera(s)).kind, FilterKind::Tent);
}

namespace {

struct IdentityCase {
    LensModel lens;
    PixelJitter jitter;
    FilterKind filter;  // for PixelJitter::Filter
};

// The light-tracing identity: a Lambertian plane of radiance L everywhere, tilted 20
// degrees and filling the view, traced from the plane's side. Points y uniform on a
// rectangle of the plane (density 1 / area) are joined to the lens by sample_wi and
// splatted with the film estimate C = L cos_plane We cos_lens / d^2 / p_area (=
// L cos_plane weight area); N = spp W H such paths resolved with spp give every pixel L.
// Per pixel the estimate is a mean of N terms x = C W H h in [0, x_max] with mean L, so its
// variance is at most x_max L / N: each pixel within 5 times the square root of that.
void check_identity(const IdentityCase& c) {
    CameraSettings s;
    s.position = {0.0f, 0.0f, 0.0f};
    s.look_at = {0.0f, 0.0f, -1.0f};
    s.width = 10;
    s.height = 8;
    s.vertical_fov_degrees = 60.0f;
    s.lens = c.lens;
    s.lens_radius = 1.5f;  // large against the focal distance: far from a pinhole
    s.lens_sigma = 0.4f;
    s.focal_distance = 6.0f;
    s.pixel_jitter = c.jitter;
    s.pixel_filter = default_filter_settings(c.filter);
    const Camera camera(s);
    SplatFilm film(s.width, s.height, splat_filter_settings(camera));
    const float margin = film.margin();

    // The plane through (0, 0, -6), normal n towards the camera; (a, b) spans it.
    const double tilt = 20.0 * std::numbers::pi / 180.0;
    const glm::dvec3 n(0.0, std::sin(tilt), std::cos(tilt));
    const glm::dvec3 a(1.0, 0.0, 0.0);
    const glm::dvec3 b = glm::cross(n, a);
    const glm::dvec3 p0(0.0, 0.0, -6.0);
    // The rectangle holding every ray from the lens (its radius, or 6 sigma: a Gaussian
    // lens point beyond has probability exp(-18) = 1.5e-8) through the image grown by the
    // margin: the corner rays' hits, and 0.5 units to spare.
    double a_lo = 1e30, a_hi = -1e30, b_lo = 1e30, b_hi = -1e30;
    const double lens_reach =
        c.lens == LensModel::Disk ? 1.5 : (c.lens == LensModel::Gaussian ? 6.0 * 0.4 : 0.0);
    const double d = camera.image_plane_distance();
    for (const double rx : {-double(margin), s.width + double(margin)}) {
        for (const double ry : {-double(margin), s.height + double(margin)}) {
            for (const double lx : {-lens_reach, lens_reach}) {
                for (const double ly : {-lens_reach, lens_reach}) {
                    const glm::dvec3 u =
                        glm::normalize(glm::dvec3(rx - 0.5 * s.width, 0.5 * s.height - ry, -d));
                    const glm::dvec3 o(lx, ly, 0.0);
                    const glm::dvec3 focus = c.lens == LensModel::Pinhole ? u : 6.0 * u;
                    const glm::dvec3 dir = glm::normalize(focus - o);
                    const double t = glm::dot(p0 - o, n) / glm::dot(dir, n);
                    ASSERT_GT(t, 0.0);
                    const glm::dvec3 hit = o + t * dir - p0;
                    a_lo = std::min(a_lo, glm::dot(hit, a));
                    a_hi = std::max(a_hi, glm::dot(hit, a));
                    b_lo = std::min(b_lo, glm::dot(hit, b));
                    b_hi = std::max(b_hi, glm::dot(hit, b));
                }
            }
        }
    }
    a_lo -= 0.5;
    a_hi += 0.5;
    b_lo -= 0.5;
    b_hi += 0.5;
    const double area = (a_hi - a_lo) * (b_hi - b_lo);

    const glm::vec3 radiance(0.5f, 1.0f, 2.0f);
    const int n_paths = librt::testing::scaled_samples(1 << 22);  // a tenth under a sanitizer
    Pcg32 rng(51, 52);
    double c_max = 0.0;  // the largest C of the green channel (radiance 1)
    for (int k = 0; k < n_paths; ++k) {
        const glm::vec2 u = rng.next_vec2();
        const glm::vec2 u_lens = rng.next_vec2();
        const glm::dvec3 y =
            p0 + (a_lo + u.x * (a_hi - a_lo)) * a + (b_lo + u.y * (b_hi - b_lo)) * b;
        const CameraWi wi = sample_wi(camera, glm::vec3(y), u_lens, margin);
        if (!wi.valid) continue;
        const double cos_plane = glm::dot(n, glm::dvec3(wi.wi));
        if (!(cos_plane > 0.0)) continue;
        // C = L cos_plane We cos_lens / d^2 / p_area, p_area = 1 / area.
        const double contribution = cos_plane * wi.weight * area;
        c_max = std::max(c_max, contribution);
        film.add(wi.raster, static_cast<float>(contribution) * radiance);
    }
    const double spp = double(n_paths) / (s.width * s.height);
    const Image image = film.resolve(spp);
    // The largest normalised filter value h: f(0)^2 / (integral f)^2; f(0) = 1 for these.
    const PixelFilter filter(splat_filter_settings(camera));
    double integral = 0.0;
    const double r = film.radius();
    constexpr int kSteps = 200000;
    for (int k = 0; k < kSteps; ++k) {
        integral += filter.evaluate_1d_precise(-r + (k + 0.5) * 2.0 * r / kSteps);
    }
    integral *= 2.0 * r / kSteps;
    const double h_max = 1.0 / (integral * integral);
    const double x_max = c_max * s.width * s.height * h_max;
    for (int ch = 0; ch < 3; ++ch) {
        const double want = radiance[ch];
        const double tolerance = 5.0 * std::sqrt(x_max * want * want / n_paths);
        double mean = 0.0;
        for (int i = 0; i < s.height; ++i) {
            for (int j = 0; j < s.width; ++j) {
                EXPECT_NEAR(image.at(j, i)[ch], want, tolerance)
                    << lens_name(c.lens) << " pixel " << j << ", " << i << " channel " << ch;
                mean += image.at(j, i)[ch];
            }
        }
        mean /= s.width * s.height;
        // The whole image's mean: terms C sum(h) W H / (W H), at most about x_max / (W H h_max)
        // times the largest sum of one splat's weights (1.03 for the Gaussian's ripple).
        const double tol_mean = 5.0 * std::sqrt(1.03 * c_max * want * want / n_paths);
        EXPECT_NEAR(mean, want, tol_mean) << lens_name(c.lens) << " channel " << ch;
    }
    EXPECT_EQ(film.clipped(), 0u);
    EXPECT_EQ(film.non_finite(), 0u);
}

}  // namespace

TEST(CameraImportance, LightTracedPlaneGivesItsRadianceInEveryPixelPinholeBox) {
    check_identity({LensModel::Pinhole, PixelJitter::Filter, FilterKind::Box});
}

TEST(CameraImportance, LightTracedPlaneGivesItsRadianceInEveryPixelPinholeGaussianJitter) {
    check_identity({LensModel::Pinhole, PixelJitter::Gaussian, FilterKind::Box});
}

TEST(CameraImportance, LightTracedPlaneGivesItsRadianceInEveryPixelDiskLensTent) {
    check_identity({LensModel::Disk, PixelJitter::Filter, FilterKind::Tent});
}

TEST(CameraImportance, LightTracedPlaneGivesItsRadianceInEveryPixelGaussianLensBox) {
    check_identity({LensModel::Gaussian, PixelJitter::Filter, FilterKind::Box});
}
