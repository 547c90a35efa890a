#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/geometry/sphere.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace librt;

namespace {

// The report's primary direction for pixel (i = row, j = column), from docs/scenes.md.
glm::vec3 report_direction(int i, int j, int w, int h, float fov_degrees) {
    const double fov = fov_degrees * 3.14159265358979323846 / 180.0;
    const glm::dvec3 d(j - w / 2.0 + 0.5, -i + h / 2.0 - 0.5, -h / (2.0 * std::tan(fov / 2.0)));
    return glm::vec3(glm::normalize(d));
}

void expect_near(const glm::vec3& a, const glm::vec3& b, float tol = 1e-6f) {
    EXPECT_NEAR(a.x, b.x, tol);
    EXPECT_NEAR(a.y, b.y, tol);
    EXPECT_NEAR(a.z, b.z, tol);
}

// Expects Camera(s) to throw an Error whose message names `parameter`.
void expect_rejects(const CameraSettings& s, const std::string& parameter) {
    try {
        const Camera camera(s);
        ADD_FAILURE() << "accepted a bad " << parameter;
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find(parameter), std::string::npos) << e.what();
    }
}

}  // namespace

TEST(Camera, CentreAndCornerDirectionsFollowTheReport) {
    const Camera camera(CameraSettings{});  // the report's camera, 512x512, 60 degrees
    for (const auto& [i, j] :
         {std::pair{255, 255}, {256, 256}, {0, 0}, {0, 511}, {511, 0}, {511, 511}, {100, 400}}) {
        Sampler sampler(0, 0, 0, 0);
        const Ray ray = camera.generate_ray(j, i, sampler);
        EXPECT_EQ(ray.origin, glm::vec3(0.0f, 0.0f, 55.0f));
        expect_near(ray.direction, report_direction(i, j, 512, 512, 60.0f));
        EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
    }
    // The two centre pixels straddle the optical axis symmetrically.
    Sampler sampler(0, 0, 0, 0);
    const Ray a = camera.generate_ray(255, 255, sampler);
    const Ray b = camera.generate_ray(256, 256, sampler);
    EXPECT_FLOAT_EQ(a.direction.x, -b.direction.x);
    EXPECT_FLOAT_EQ(a.direction.y, -b.direction.y);
}

TEST(Camera, NonSquareImageUsesVerticalFov) {
    CameraSettings s;
    s.width = 320;
    s.height = 200;
    s.vertical_fov_degrees = 45.0f;
    const Camera camera(s);
    Sampler sampler(1, 2, 3, 4);
    const Ray top = camera.generate_ray(160, 0, sampler);
    expect_near(top.direction, report_direction(0, 160, 320, 200, 45.0f));
    // The top edge of the image (row -0.5) is half the vertical fov above the axis.
    const float slope = (100.0f) / (100.0f / std::tan(glm::radians(22.5f)));
    const Ray row0 = camera.generate_ray(159, 0, sampler);
    EXPECT_NEAR(row0.direction.y / -row0.direction.z, slope * 99.5f / 100.0f, 1e-5f);
}

TEST(Camera, LookAtBasisRotatesTheReportFrame) {
    CameraSettings s;
    s.position = {10.0f, 0.0f, 0.0f};
    s.look_at = {0.0f, 0.0f, 0.0f};  // looking down -x: image right is -z
    const Camera camera(s);
    expect_near(camera.forward(), {-1.0f, 0.0f, 0.0f});
    expect_near(camera.right(), {0.0f, 0.0f, -1.0f});
    expect_near(camera.true_up(), {0.0f, 1.0f, 0.0f});
    Sampler sampler(0, 0, 0, 0);
    const Ray ray = camera.generate_ray(0, 0, sampler);
    const glm::vec3 local = report_direction(0, 0, 512, 512, 60.0f);  // camera space
    expect_near(ray.direction, {-(-local.z), local.y, -local.x});
}

TEST(Camera, WithoutJitterEverySampleGivesTheSameRay) {
    const Camera camera(CameraSettings{});
    Sampler first(7, 9, 0, 0);
    const Ray reference = camera.generate_ray(7, 9, first);
    for (std::uint32_t s = 1; s < 50; ++s) {
        Sampler sampler(7, 9, s, 123);
        const Ray ray = camera.generate_ray(7, 9, sampler);
        EXPECT_EQ(ray.origin, reference.origin);
        EXPECT_EQ(ray.direction, reference.direction);
    }
}

TEST(Camera, DrawsTheSameSamplesWithOrWithoutJitter) {
    CameraSettings plain;
    CameraSettings jittered;
    jittered.pixel_jitter = PixelJitter::Gaussian;
    jittered.lens = LensModel::Disk;
    Sampler a(3, 4, 5, 6);
    Sampler b(3, 4, 5, 6);
    (void)Camera(plain).generate_ray(3, 4, a);
    (void)Camera(jittered).generate_ray(3, 4, b);
    EXPECT_EQ(a.next_1d(), b.next_1d());
}

TEST(Camera, GaussianPixelJitterSpreadsAroundThePixelCentre) {
    CameraSettings s;
    s.pixel_jitter = PixelJitter::Gaussian;
    const Camera camera(s);
    const float d = 512.0f / (2.0f * std::tan(glm::radians(30.0f)));
    double sum_x = 0, sum_xx = 0;
    constexpr int n = 20000;
    for (int k = 0; k < n; ++k) {
        Sampler sampler(256, 256, static_cast<std::uint32_t>(k), 1);
        const Ray ray = camera.generate_ray(256, 256, sampler);
        // Back to the image plane (pixels): x = -d * dir.x / dir.z.
        const double x = -d * ray.direction.x / ray.direction.z - 0.5;  // offset from centre
        sum_x += x;
        sum_xx += x * x;
    }
    const double mean = sum_x / n;
    const double sigma = std::sqrt(sum_xx / n - mean * mean);
    EXPECT_NEAR(mean, 0.0, 0.02);
    EXPECT_NEAR(sigma, 0.5, 0.02);
}

TEST(Camera, LensJitterKeepsTheFocalPointFixed) {
    for (const LensModel lens : {LensModel::Gaussian, LensModel::Disk}) {
        CameraSettings s;
        s.lens = lens;
        s.lens_sigma = 1.0f;
        s.lens_radius = 2.0f;
        s.focal_distance = 55.0f;
        const Camera camera(s);
        CameraSettings pinhole_settings = s;
        pinhole_settings.lens = LensModel::Pinhole;
        const Camera pinhole(pinhole_settings);
        for (const auto& [x, y] : {std::pair{256, 256}, {0, 0}, {511, 100}}) {
            Sampler p(0, 0, 0, 0);
            const Ray axis = pinhole.generate_ray(x, y, p);
            const glm::vec3 focal_point = axis.at(55.0f);
            float spread = 0.0f;
            for (std::uint32_t k = 0; k < 64; ++k) {
                Sampler sampler(static_cast<std::uint32_t>(x), static_cast<std::uint32_t>(y), k, 9);
                const Ray ray = camera.generate_ray(x, y, sampler);
                spread = std::max(spread, glm::length(ray.origin - axis.origin));
                // The origin stays in the camera's x-y plane.
                EXPECT_NEAR(glm::dot(ray.origin - axis.origin, camera.forward()), 0.0f, 1e-5f);
                // The ray passes through the focal point: distance from it to the line.
                const glm::vec3 to_focal = focal_point - ray.origin;
                const float off_line = glm::length(glm::cross(to_focal, ray.direction));
                EXPECT_LT(off_line, 1e-4f) << "pixel " << x << "," << y;
                EXPECT_GT(glm::dot(to_focal, ray.direction), 0.0f);
            }
            EXPECT_GT(spread, 0.1f);  // the origins really moved
        }
    }
}

TEST(Camera, InvalidSettingsNameTheParameter) {
    const auto with = [](auto change) {
        CameraSettings s;
        change(s);
        return s;
    };
    expect_rejects(with([](CameraSettings& s) { s.width = 0; }), "width = 0");
    expect_rejects(with([](CameraSettings& s) { s.width = 65537; }), "width = 65537");
    expect_rejects(with([](CameraSettings& s) { s.height = -3; }), "height = -3");
    expect_rejects(with([](CameraSettings& s) { s.vertical_fov_degrees = 0.0f; }),
                   "vertical_fov_degrees");
    expect_rejects(with([](CameraSettings& s) { s.vertical_fov_degrees = 180.0f; }),
                   "vertical_fov_degrees = 180");
    expect_rejects(with([](CameraSettings& s) { s.vertical_fov_degrees = NAN; }),
                   "vertical_fov_degrees");
    expect_rejects(with([](CameraSettings& s) { s.position.x = INFINITY; }), "position");
    expect_rejects(with([](CameraSettings& s) { s.look_at = s.position; }), "look_at");
    expect_rejects(with([](CameraSettings& s) { s.up = {0.0f, 0.0f, 1.0f}; }), "up");
    expect_rejects(with([](CameraSettings& s) { s.up = {0.0f, 0.0f, 0.0f}; }), "up");
    expect_rejects(with([](CameraSettings& s) { s.pixel_sigma = -0.5f; }), "pixel_sigma = -0.5");
    expect_rejects(with([](CameraSettings& s) { s.lens_sigma = -1.0f; }), "lens_sigma = -1");
    expect_rejects(with([](CameraSettings& s) { s.lens_radius = NAN; }), "lens_radius");
    expect_rejects(with([](CameraSettings& s) { s.focal_distance = 0.0f; }), "focal_distance = 0");
    EXPECT_NO_THROW(Camera(with([](CameraSettings& s) {
        s.width = 1;
        s.height = 65536;
    })));
}

TEST(Camera, WithoutClipsRaysSpanTheWholeLine) {
    const Camera camera(CameraSettings{});
    Sampler sampler(1, 2, 3, 4);
    const Ray ray = camera.generate_ray(10, 20, sampler);
    EXPECT_EQ(ray.t_min, 0.0f);
    EXPECT_EQ(ray.t_max, std::numeric_limits<float>::infinity());
}

TEST(Camera, NearAndFarClipAreDepthPlanesInFrontOfTheLens) {
    // smallpt's camera: the scene starts 140 units in front of it along the view axis.
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk, LensModel::Gaussian}) {
        CameraSettings s;
        s.position = {50.0f, 52.0f, 295.6f};
        s.look_at = {50.0f, 52.0f - 0.042612f, 294.6f};
        s.vertical_fov_degrees = 54.4f;
        s.width = 256;
        s.height = 192;
        s.pixel_jitter = PixelJitter::Gaussian;
        s.lens = lens;
        s.lens_radius = 3.0f;
        s.near_clip = 140.0f;
        s.far_clip = 300.0f;
        const Camera camera(s);
        for (const auto& [x, y] : {std::pair{0, 0}, {255, 191}, {128, 96}, {3, 180}}) {
            Sampler sampler(SamplerKind::Sobol, std::uint32_t(x), std::uint32_t(y), 5, 1);
            const Ray ray = camera.generate_ray(x, y, sampler);
            EXPECT_NEAR(glm::length(ray.direction), 1.0f, 1e-6f);
            // The depth of the clip points, measured along the axis from the lens plane
            // (the origin lies in it), is near and far; t is their distance from the origin.
            EXPECT_NEAR(glm::dot(ray.origin - s.position, camera.forward()), 0.0f, 1e-4f);
            EXPECT_NEAR(glm::dot(ray.at(ray.t_min) - ray.origin, camera.forward()), 140.0f, 1e-3f);
            EXPECT_NEAR(glm::dot(ray.at(ray.t_max) - ray.origin, camera.forward()), 300.0f, 2e-3f);
            EXPECT_GE(ray.t_min, 140.0f);  // off-axis rays travel further to reach the plane
        }
    }
    // Only a far clip: t_min stays exactly 0.
    CameraSettings far_only;
    far_only.far_clip = 10.0f;
    Sampler sampler(0, 0, 0, 0);
    const Ray ray = Camera(far_only).generate_ray(256, 256, sampler);
    EXPECT_EQ(ray.t_min, 0.0f);
    EXPECT_NEAR(ray.t_max * glm::dot(ray.direction, glm::vec3(0, 0, -1)), 10.0f, 1e-5f);
}

TEST(Camera, NearClipDistanceIsTMinOfEveryRay) {
    // Off-axis pixels (corners) and the centre, pinhole and both thin lenses: in Distance
    // mode t_min is near_clip itself, in Plane mode near_clip / cos, larger off the axis.
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk, LensModel::Gaussian}) {
        for (const NearClipMode mode : {NearClipMode::Plane, NearClipMode::Distance}) {
            CameraSettings s;
            s.width = 96;
            s.height = 64;
            s.vertical_fov_degrees = 70.0f;
            s.pixel_jitter = PixelJitter::Gaussian;
            s.lens = lens;
            s.lens_radius = 0.5f;
            s.lens_sigma = 0.3f;
            s.near_clip = 2.0f;
            s.near_clip_mode = mode;
            s.far_clip = 50.0f;
            const Camera camera(s);
            for (const auto& [x, y] : {std::pair{0, 0}, {95, 63}, {48, 32}, {0, 63}, {95, 0}}) {
                for (std::uint32_t k = 0; k < 8; ++k) {
                    Sampler sampler(std::uint32_t(x), std::uint32_t(y), k, 3);
                    const Ray ray = camera.generate_ray(x, y, sampler);
                    const float cos_axis = glm::dot(ray.direction, camera.forward());
                    if (mode == NearClipMode::Distance) {
                        EXPECT_EQ(ray.t_min, 2.0f) << x << ' ' << y;
                    } else {
                        EXPECT_NEAR(ray.t_min, 2.0f / cos_axis, 1e-5f) << x << ' ' << y;
                    }
                    // The far clip is a plane in both modes.
                    EXPECT_NEAR(ray.t_max, 50.0f / cos_axis, 1e-4f) << x << ' ' << y;
                    if (x != 48 && mode == NearClipMode::Plane) {
                        EXPECT_GT(ray.t_min, 2.2f) << x << ' ' << y;  // corners: cos < 0.9
                    }
                }
            }
        }
    }
}

TEST(Camera, NearClipDistanceSeesASphereAroundTheCameraEverywhere) {
    // A sphere centred on the camera, of radius a little beyond near_clip: every ray of a
    // distance clip starts inside it and sees it; a near clip plane at the same depth cuts
    // the sphere off where near_clip / cos exceeds the radius, at the image's corners.
    const Sphere sphere{CameraSettings{}.position, 10.2f};
    for (const LensModel lens : {LensModel::Pinhole, LensModel::Disk}) {
        for (const NearClipMode mode : {NearClipMode::Plane, NearClipMode::Distance}) {
            CameraSettings s;  // 60 degrees vertical, square: the corners are 39 degrees off
            s.width = 32;
            s.height = 32;
            s.lens = lens;
            s.lens_radius = 0.1f;
            s.near_clip = 10.0f;
            s.near_clip_mode = mode;
            const Camera camera(s);
            int seen = 0, corners_seen = 0;
            for (int y = 0; y < 32; ++y) {
                for (int x = 0; x < 32; ++x) {
                    Sampler sampler(std::uint32_t(x), std::uint32_t(y), 0, 1);
                    const bool hit =
                        intersect(sphere, camera.generate_ray(x, y, sampler)).has_value();
                    seen += hit;
                    const bool corner = (x == 0 || x == 31) && (y == 0 || y == 31);
                    corners_seen += corner && hit;
                    if (x == 16 && y == 16) {
                        EXPECT_TRUE(hit);  // on the axis, both modes
                    }
                }
            }
            if (mode == NearClipMode::Distance) {
                EXPECT_EQ(seen, 32 * 32);
            } else {
                EXPECT_EQ(corners_seen, 0);
                EXPECT_LT(seen, 32 * 32 / 2);  // only within acos(10 / 10.2) = 11 degrees
            }
        }
    }
}

TEST(Camera, ClipAndFilterSettingsAreValidated) {
    const auto with = [](auto change) {
        CameraSettings s;
        change(s);
        return s;
    };
    expect_rejects(with([](CameraSettings& s) { s.near_clip = -1.0f; }), "near_clip = -1");
    expect_rejects(with([](CameraSettings& s) { s.near_clip = NAN; }), "near_clip");
    expect_rejects(with([](CameraSettings& s) { s.near_clip = INFINITY; }), "near_clip");
    expect_rejects(with([](CameraSettings& s) { s.near_clip_mode = static_cast<NearClipMode>(2); }),
                   "near_clip_mode = 2");
    expect_rejects(with([](CameraSettings& s) { s.far_clip = 0.0f; }), "far_clip = 0");
    expect_rejects(with([](CameraSettings& s) { s.far_clip = NAN; }), "far_clip");
    expect_rejects(with([](CameraSettings& s) {
                       s.near_clip = 5.0f;
                       s.far_clip = 5.0f;
                   }),
                   "far_clip = 5");
    expect_rejects(with([](CameraSettings& s) { s.pixel_jitter = static_cast<PixelJitter>(9); }),
                   "pixel_jitter = 9");
    expect_rejects(with([](CameraSettings& s) {
                       s.pixel_jitter = PixelJitter::Filter;
                       s.pixel_filter.radius = -2.0f;
                   }),
                   "pixel_filter: filter radius = -2");
    // A bad filter is not an error while it is not used.
    EXPECT_NO_THROW(Camera(with([](CameraSettings& s) { s.pixel_filter.radius = -2.0f; })));
}

TEST(Camera, GaussianJitterIsTheUntruncatedGaussianFilter) {
    CameraSettings jitter;
    jitter.pixel_jitter = PixelJitter::Gaussian;
    jitter.pixel_sigma = 0.5f;
    CameraSettings filter = jitter;
    filter.pixel_jitter = PixelJitter::Filter;
    filter.pixel_filter.kind = FilterKind::Gaussian;
    filter.pixel_filter.sigma = 0.5f;
    filter.pixel_filter.radius = std::numeric_limits<float>::infinity();
    const Camera a(jitter), b(filter);
    for (std::uint32_t k = 0; k < 200; ++k) {
        Sampler sa(3, 4, k, 5), sb(3, 4, k, 5);
        const CameraRay ra = a.sample_ray(3, 4, sa);
        const CameraRay rb = b.sample_ray(3, 4, sb);
        EXPECT_EQ(ra.ray.direction, rb.ray.direction);
        EXPECT_EQ(ra.weight, 1.0f);
        EXPECT_EQ(rb.weight, 1.0f);
    }
}

TEST(Camera, FilterOffsetsComeFromTheSamplersFirstPair) {
    // A box filter of radius 0.5 with the Sobol sampler: the first 16 samples of a pixel
    // land one in each of the 4x4 sub-pixel cells (the sampler's first pair is stratified
    // and the box's inversion is monotone).
    CameraSettings s;
    s.pixel_jitter = PixelJitter::Filter;
    s.pixel_filter = default_filter_settings(FilterKind::Box);
    const Camera camera(s);
    const float d = 512.0f / (2.0f * std::tan(glm::radians(30.0f)));
    std::vector<int> cells(16, 0);
    for (std::uint32_t k = 0; k < 16; ++k) {
        Sampler sampler(SamplerKind::Sobol, 256, 256, k, 3);
        const CameraRay r = camera.sample_ray(256, 256, sampler);
        EXPECT_EQ(sampler.dimension(), 4u);  // pixel and lens pairs, drawn either way
        // Back to the image plane, as offsets from the pixel centre (0.5, -0.5).
        const double x = -d * r.ray.direction.x / r.ray.direction.z - 0.5;
        const double y = -d * r.ray.direction.y / r.ray.direction.z + 0.5;
        ASSERT_LT(std::abs(x), 0.5 + 1e-3);
        ASSERT_LT(std::abs(y), 0.5 + 1e-3);
        const int cx = std::clamp(static_cast<int>((x + 0.5) * 4.0), 0, 3);
        const int cy = std::clamp(static_cast<int>((y + 0.5) * 4.0), 0, 3);
        ++cells[cx * 4 + cy];
    }
    for (const int c : cells) EXPECT_EQ(c, 1);
    // A Mitchell filter hands its signed weight to sample_ray.
    CameraSettings m = s;
    m.pixel_filter = default_filter_settings(FilterKind::Mitchell);
    const Camera mitchell(m);
    bool negative = false;
    for (std::uint32_t k = 0; k < 256; ++k) {
        Sampler sampler(7, 7, k, 1);
        const CameraRay r = mitchell.sample_ray(7, 7, sampler);
        negative = negative || r.weight < 0.0f;
        EXPECT_GT(std::abs(r.weight), 1.0f);  // (integral |f| / integral f)^2 > 1
    }
    EXPECT_TRUE(negative);
}
