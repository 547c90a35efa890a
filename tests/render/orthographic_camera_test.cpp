// The orthographic camera: parallel rays from the camera plane, a known world point seen at
// the pixel xmag / ymag predict (the basis and the footprint worked out by hand here, not
// taken from the camera), clip planes as plain distances, the same random numbers drawn as
// a perspective camera, and its parameters validated.

#include <librt/core/error.h>
#include <librt/film/camera.h>
#include <librt/geometry/sphere.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

using namespace librt;

namespace {

/// Camera at (-10, 1, 2) looking along +x with world up +z: by hand, image right is
/// forward x up = (1,0,0) x (0,0,1) = (0,-1,0) and image up is +z.
CameraSettings side_camera() {
    CameraSettings s;
    s.projection = Projection::Orthographic;
    s.position = {-10.0f, 1.0f, 2.0f};
    s.look_at = {0.0f, 1.0f, 2.0f};
    s.up = {0.0f, 0.0f, 1.0f};
    s.width = 160;
    s.height = 60;
    s.xmag = 4.0f;  // 8 units over 160 columns: 0.05 per column
    s.ymag = 1.5f;  // 3 units over 60 rows: 0.05 per row
    return s;
}

const glm::vec3 kRight{0.0f, -1.0f, 0.0f};
const glm::vec3 kUp{0.0f, 0.0f, 1.0f};
const glm::vec3 kForward{1.0f, 0.0f, 0.0f};

std::string rejection(const CameraSettings& s) {
    try {
        const Camera camera(s);
    } catch (const Error& e) {
        return e.what();
    }
    return "accepted";
}

}  // namespace

TEST(OrthographicCamera, RaysAreParallelAndStartOnTheCameraPlane) {
    for (const PixelJitter jitter : {PixelJitter::None, PixelJitter::Gaussian}) {
        CameraSettings s = side_camera();
        s.pixel_jitter = jitter;
        const Camera camera(s);
        for (const auto& [x, y] : {std::pair{0, 0}, {159, 59}, {80, 30}, {7, 52}, {120, 3}}) {
            for (std::uint32_t k = 0; k < 8; ++k) {
                Sampler sampler(std::uint32_t(x), std::uint32_t(y), k, 3);
                const Ray ray = camera.generate_ray(x, y, sampler);
                EXPECT_EQ(ray.direction, kForward);  // exactly the axis, for every pixel
                EXPECT_NEAR(glm::dot(ray.origin - s.position, kForward), 0.0f, 1e-5f);
                EXPECT_EQ(ray.t_min, 0.0f);
                EXPECT_TRUE(std::isinf(ray.t_max));
            }
        }
    }
}

TEST(OrthographicCamera, PixelOfAKnownPointIsPredictedByXmagAndYmag) {
    const CameraSettings s = side_camera();
    const Camera camera(s);
    // A point 10 ahead, 1.83 right and 0.62 down of the camera: by glTF's projection it
    // lands at normalised x = 1.83 / xmag, y = -0.62 / ymag, i.e. column (x + 1) W / 2 and
    // row (1 - y) H / 2 (rows top down).
    const float right = 1.83f, up = -0.62f;
    const glm::vec3 q = s.position + 10.0f * kForward + right * kRight + up * kUp;
    const double col = (right / 4.0 + 1.0) * 160.0 / 2.0;  // 116.6
    const double row = (1.0 - up / 1.5) * 60.0 / 2.0;      // 42.4
    const int px = int(std::floor(col)), py = int(std::floor(row));
    ASSERT_EQ(px, 116);
    ASSERT_EQ(py, 42);
    // The centre ray of that pixel passes q at the offset of q from the pixel centre.
    Sampler sampler(std::uint32_t(px), std::uint32_t(py), 0, 0);
    const Ray ray = camera.generate_ray(px, py, sampler);
    const glm::vec3 d = q - ray.origin;
    EXPECT_NEAR(glm::dot(d, kForward), 10.0f, 1e-4f);
    // The pixel centre is at column px + 0.5, 0.05 units per column and row.
    EXPECT_NEAR(glm::dot(d, kRight), float((col - (px + 0.5)) * 0.05), 1e-5f);
    EXPECT_NEAR(glm::dot(d, kUp), float(-(row - (py + 0.5)) * 0.05), 1e-5f);

    // Through a scene: a sphere of radius 0.04 at q (0.007 from the pixel's centre ray) is
    // hit from that pixel, not from the pixels two away (0.095 or more from their rays),
    // whatever the distance (no perspective shrinking).
    for (const float ahead : {3.0f, 10.0f, 500.0f}) {
        const glm::vec3 centre = s.position + ahead * kForward + right * kRight + up * kUp;
        Scene scene;
        const std::uint32_t m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
        scene.add_sphere(Sphere{centre, 0.04f}, m);
        scene.commit();
        for (int dx = -2; dx <= 2; dx += 2) {
            for (int dy = -2; dy <= 2; dy += 2) {
                Sampler sa(std::uint32_t(px + dx), std::uint32_t(py + dy), 0, 0);
                Hit hit;
                const bool got = scene.intersect(camera.generate_ray(px + dx, py + dy, sa), hit);
                EXPECT_EQ(got, dx == 0 && dy == 0)
                    << "ahead " << ahead << " offset " << dx << "," << dy;
                if (got) {
                    EXPECT_NEAR(hit.t, ahead - 0.04f, 1e-3f * ahead);
                }
            }
        }
    }
}

TEST(OrthographicCamera, ImageEdgesAreAtXmagAndYmagWhateverTheSize) {
    // 40 x 40 pixels over a 8 x 3 view: the pixels are not square, as glTF stretches.
    CameraSettings s = side_camera();
    s.width = 40;
    s.height = 40;
    const Camera camera(s);
    Sampler a(0, 0, 0, 0), b(39, 39, 0, 0);
    const Ray top_left = camera.generate_ray(0, 0, a);
    const Ray bottom_right = camera.generate_ray(39, 39, b);
    // Pixel centres sit half a pixel (8 / 40 / 2 = 0.1 across, 3 / 40 / 2 = 0.0375 up)
    // inside the edges at -xmag .. xmag and ymag .. -ymag.
    EXPECT_NEAR(glm::dot(top_left.origin - s.position, kRight), -4.0f + 0.1f, 1e-5f);
    EXPECT_NEAR(glm::dot(top_left.origin - s.position, kUp), 1.5f - 0.0375f, 1e-5f);
    EXPECT_NEAR(glm::dot(bottom_right.origin - s.position, kRight), 4.0f - 0.1f, 1e-5f);
    EXPECT_NEAR(glm::dot(bottom_right.origin - s.position, kUp), -1.5f + 0.0375f, 1e-5f);
}

TEST(OrthographicCamera, ClipPlanesAreDistancesAlongTheAxis) {
    CameraSettings s = side_camera();
    s.near_clip = 2.5f;
    s.far_clip = 7.0f;
    s.pixel_jitter = PixelJitter::Gaussian;
    const Camera camera(s);
    for (const auto& [x, y] : {std::pair{0, 0}, {159, 59}, {33, 44}}) {
        Sampler sampler(std::uint32_t(x), std::uint32_t(y), 1, 2);
        const Ray ray = camera.generate_ray(x, y, sampler);
        EXPECT_EQ(ray.t_min, 2.5f);
        EXPECT_EQ(ray.t_max, 7.0f);
    }
}

TEST(OrthographicCamera, DrawsTheSameSamplesAsAPerspectiveCamera) {
    // Two 2D samples per ray whatever the projection, so an integrator's numbers after the
    // camera do not depend on it.
    CameraSettings ortho = side_camera();
    ortho.pixel_jitter = PixelJitter::Gaussian;
    CameraSettings persp = ortho;
    persp.projection = Projection::Perspective;
    persp.lens = LensModel::Disk;
    Sampler a(SamplerKind::Sobol, 3, 4, 5, 6), b(SamplerKind::Sobol, 3, 4, 5, 6);
    (void)Camera(ortho).generate_ray(3, 4, a);
    (void)Camera(persp).generate_ray(3, 4, b);
    EXPECT_EQ(a.next_2d(), b.next_2d());
}

TEST(OrthographicCamera, InvalidSettingsNameTheParameter) {
    const auto with = [](auto change) {
        CameraSettings s = side_camera();
        change(s);
        return s;
    };
    const auto expect = [](const CameraSettings& s, const std::string& part) {
        const std::string message = rejection(s);
        EXPECT_NE(message.find(part), std::string::npos) << message;
    };
    expect(with([](CameraSettings& s) { s.xmag = 0.0f; }),
           "camera xmag = 0: must be finite and > 0");
    expect(with([](CameraSettings& s) { s.ymag = -1.0f; }), "camera ymag = -1");
    expect(with([](CameraSettings& s) { s.xmag = NAN; }), "camera xmag = nan");
    expect(with([](CameraSettings& s) { s.ymag = 3e38f; }), "camera ymag = 3e+38");
    expect(with([](CameraSettings& s) { s.lens = LensModel::Disk; }),
           "must be Pinhole for an orthographic camera");
    expect(with([](CameraSettings& s) { s.projection = static_cast<Projection>(7); }),
           "camera projection = 7");
    // The perspective field of view is not used, so not checked; the same for xmag with a
    // perspective camera.
    EXPECT_EQ(rejection(with([](CameraSettings& s) { s.vertical_fov_degrees = 0.0f; })),
              "accepted");
    EXPECT_EQ(rejection(with([](CameraSettings& s) {
                  s.projection = Projection::Perspective;
                  s.xmag = 0.0f;
              })),
              "accepted");
}
