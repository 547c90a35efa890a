// A sphere light buried in an opaque wall sphere (sphere_light_cuts.h): the MIS path
// tracer, whose light samples see only the cap a point can see, estimates the same image
// as the brute-force path tracer (emitters found by BSDF sampling only), over the whole
// image and 4 x 4 blocks, within 5 standard errors: in a smallpt-like box (the room inside
// every wall's ball, the light in the ceiling's) and in a room of the report's orientation
// (the room outside the walls' balls, the light mostly above the ceiling). Both views show
// the ceiling around the light, whose points lie on the burying sphere itself.

#include "integrator_test_util.h"

#include <librt/integrator/integrators.h>
#include <librt/light/sphere_light.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

namespace librt {
namespace {

using testing::add_room;
using testing::Pinhole;
using testing::region;
using testing::RegionEstimate;
using testing::render_stats;
using testing::StatImage;

void expect_same(const RegionEstimate& a, const RegionEstimate& b, const std::string& where) {
    for (int c = 0; c < 3; ++c) {
        const double tol = 5.0 * std::sqrt(a.se2[c] + b.se2[c]);
        EXPECT_LE(std::fabs(a.mean[c] - b.mean[c]), tol)
            << where << " channel " << c << ": " << a.mean[c] << " vs " << b.mean[c];
    }
}

void expect_same_image(const StatImage& a, const StatImage& b, const std::string& what) {
    const int w = a.width, h = a.height;
    expect_same(region(a, 0, 0, w, h), region(b, 0, 0, w, h), what + ", whole image");
    for (int by = 0; by < 4; ++by)
        for (int bx = 0; bx < 4; ++bx)
            expect_same(region(a, bx * w / 4, by * h / 4, (bx + 1) * w / 4, (by + 1) * h / 4),
                        region(b, bx * w / 4, by * h / 4, (bx + 1) * w / 4, (by + 1) * h / 4),
                        what + ", block " + std::to_string(bx) + "," + std::to_string(by));
}

// Renders both, checks the light was clipped (it has cuts and the MIS image's noise is
// below the brute force's per sample) and that the images agree.
void expect_mis_matches_brute(const Scene& scene, const Pinhole& cam, const std::string& what) {
    const auto& light = std::get<SphereLight>(scene.lights()[0].source);
    ASSERT_NE(light.cuts, nullptr) << what;
    PathTracer mis(PathTracerSettings{5, false});
    BruteForcePathTracer brute(PathTracerSettings{5, false});
    const StatImage a = render_stats(scene, mis, cam, 256, 31);
    const StatImage b = render_stats(scene, brute, cam, 2048, 32);
    EXPECT_EQ(mis.nonfinite_count() + brute.nonfinite_count(), 0u);
    expect_same_image(a, b, what);
    // Power: the whole image's difference is resolved to 3 %.
    const RegionEstimate wa = region(a, 0, 0, cam.width, cam.height);
    const RegionEstimate wb = region(b, 0, 0, cam.width, cam.height);
    for (int c = 0; c < 3; ++c) EXPECT_LT(std::sqrt(wa.se2[c] + wb.se2[c]), 0.03 * wb.mean[c]);
}

TEST(BuriedSphereLight, MisMatchesBruteForceInASmallptLikeBox) {
    // smallpt's walls (radius 1e5, in double); its light shrunk to radius 60 and sunk 4
    // units below the ceiling so that brute force finds it often enough.
    Scene scene;
    const auto diffuse = [&](glm::vec3 c) { return scene.add_material(Material::diffuse(c)); };
    scene.add_sphere(glm::dvec3(1e5 + 1, 40.8, 81.6), 1e5, diffuse({0.75f, 0.25f, 0.25f}));
    scene.add_sphere(glm::dvec3(-1e5 + 99, 40.8, 81.6), 1e5, diffuse({0.25f, 0.25f, 0.75f}));
    scene.add_sphere(glm::dvec3(50, 40.8, 1e5), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere(glm::dvec3(50, 40.8, -1e5 + 170), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere(glm::dvec3(50, 1e5, 81.6), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere(glm::dvec3(50, -1e5 + 81.6, 81.6), 1e5, diffuse(glm::vec3(0.75f)));
    scene.add_sphere(glm::dvec3(30, 16.5, 60), 16.5, scene.add_material(Material::mirror()));
    (void)scene.add_sphere_light({{{50.0f, 81.6f + 60.0f - 4.0f, 81.6f}, 60.0f}, glm::vec3(4.0f)});
    scene.commit();
    Pinhole cam;
    cam.eye = {50, 40, 165};
    cam.forward = glm::normalize(glm::vec3(0, 0.35f, -1));
    cam.up = glm::normalize(glm::cross(glm::cross(cam.forward, glm::vec3(0, 1, 0)), cam.forward));
    cam.fov_degrees = 70.0f;
    cam.width = cam.height = 16;
    expect_mis_matches_brute(scene, cam, "smallpt-like box");
}

TEST(BuriedSphereLight, MisMatchesBruteForceInTheReportsRoomOrientation) {
    // The report's room: the ceiling is the ball (0, 1000, 0) r 940 (plane y = 60) and
    // the room outside it; the light's centre is 6 above that plane, 4 of its 10 below.
    Scene scene;
    add_room(scene);
    (void)scene.add_sphere_light({{{0, 66, -20}, 10.0f}, glm::vec3(20.0f)});
    scene.commit();
    Pinhole cam;
    cam.eye = {0, 0, 55};
    cam.forward = glm::normalize(glm::vec3(0, 0.5f, -1));
    cam.up = glm::normalize(glm::cross(glm::cross(cam.forward, glm::vec3(0, 1, 0)), cam.forward));
    cam.width = cam.height = 16;
    expect_mis_matches_brute(scene, cam, "report room");
}

}  // namespace
}  // namespace librt
