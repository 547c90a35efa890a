// Spheres given in double through Scene::add_sphere(dvec3, double, material) (issue 15,
// item 5): smallpt's walls of radius 1e5 stay exactly where their author put them.

#include <librt/core/error.h>
#include <librt/scene/scene.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace librt {
namespace {

constexpr double kWall = 1e5;  // smallpt's wall radius
constexpr double kCap = 0.27;  // how far the light pokes below the wall

/// A wall of radius 1e5 whose lowest point is at y = 0.27, and under it a sphere of
/// radius 600 touching y = 0: a cap of height 0.27 of the sphere shows below the wall,
/// as smallpt's light below its ceiling. `exact`: the wall through the double overload.
struct CapScene {
    Scene scene;
    std::uint32_t wall = 0;
    std::uint32_t light = 0;

    explicit CapScene(bool exact) {
        const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
        const glm::dvec3 centre(0.0, kWall + kCap, 0.0);
        wall = exact ? scene.add_sphere(centre, kWall, m)
                     : scene.add_sphere(Sphere{glm::vec3(centre), float(kWall)}, m);
        light = scene.add_sphere(Sphere{{0.0f, 600.0f, 0.0f}, 600.0f}, m);
        scene.commit();
    }

    /// The object a ray straight up from (x, -1, 0) meets first.
    std::uint32_t hit_from_below(double x) const {
        Ray ray;
        ray.origin = {float(x), -1.0f, 0.0f};
        ray.direction = {0.0f, 1.0f, 0.0f};
        Hit hit;
        return scene.intersect(ray, hit) ? hit.object_id : kInvalidId;
    }
};

/// Radius of the cap: where the light's surface 600 - sqrt(600^2 - r^2) meets the wall's
/// 1e5 + 0.27 - sqrt(1e10 - r^2), by bisection in long double.
double exact_cap_radius() {
    long double lo = 0.0L, hi = 20.0L;
    for (int i = 0; i < 200; ++i) {
        const long double r = 0.5L * (lo + hi);
        const long double light = 600.0L - std::sqrt(360000.0L - r * r);
        const long double wall = (long double)kWall + (long double)kCap - std::sqrt(1e10L - r * r);
        (light < wall ? lo : hi) = r;
    }
    return double(lo);
}

// The first hit of a ray going straight up lies at exactly y = 0.27, to float output
// precision; the float wall (its centre rounded to 100000.2734375) is 0.0034 off.
TEST(DoubleSphere, WallAtItsExactHeight) {
    const CapScene exact(true), rounded(false);
    Ray ray;
    ray.origin = {20.0f, 0.0f, 0.0f};  // beside the light
    ray.direction = {0.0f, 1.0f, 0.0f};
    // Exact distance: the wall's height above x = 20: 1e5 + 0.27 - sqrt(1e10 - 400).
    const double t = kWall + kCap - std::sqrt(kWall * kWall - 400.0);
    Hit hit;
    ASSERT_TRUE(exact.scene.intersect(ray, hit));
    EXPECT_EQ(hit.object_id, exact.wall);
    EXPECT_LE(std::fabs(double(hit.t) - t), 2.0 * std::numeric_limits<float>::epsilon() * t);
    ASSERT_TRUE(rounded.scene.intersect(ray, hit));
    EXPECT_GT(std::fabs(double(hit.t) - t), 1e-3);  // the trap this overload removes
}

// The cap of the light below the wall has its exact radius (about 18, as smallpt's): rays
// 0.1% inside it meet the light and 0.1% outside meet the wall. With the rounded wall the
// cap is 0.6% wider, and the ray just outside still meets the light.
TEST(DoubleSphere, ExactCapBelowAWall) {
    const double r = exact_cap_radius();
    ASSERT_GT(r, 1.0);
    const CapScene exact(true), rounded(false);
    for (const double sign : {-1.0, 1.0}) {
        EXPECT_EQ(exact.hit_from_below(sign * r * 0.999), exact.light);
        EXPECT_EQ(exact.hit_from_below(sign * r * 1.001), exact.wall);
        EXPECT_EQ(rounded.hit_from_below(sign * r * 1.001), rounded.light);
    }
}

// Bad double input is refused with the parameter and its value, as for float spheres;
// values float cannot hold too.
TEST(DoubleSphere, BadInputIsAnError) {
    Scene scene;
    const auto m = scene.add_material(Material::diffuse(glm::vec3(0.5f)));
    const double nan = std::numeric_limits<double>::quiet_NaN();
    EXPECT_THROW((void)scene.add_sphere(glm::dvec3(nan, 0.0, 0.0), 1.0, m), Error);
    EXPECT_THROW((void)scene.add_sphere(glm::dvec3(1e39, 0.0, 0.0), 1.0, m), Error);
    EXPECT_THROW((void)scene.add_sphere(glm::dvec3(0.0), 0.0, m), Error);
    EXPECT_THROW((void)scene.add_sphere(glm::dvec3(0.0), 1e-50, m), Error);
    EXPECT_THROW((void)scene.add_sphere(glm::dvec3(0.0), 1.0, 99u), Error);
    try {
        (void)scene.add_sphere(glm::dvec3(0.0), -2.0, m);
        FAIL() << "no error";
    } catch (const Error& e) {
        EXPECT_NE(std::string(e.what()).find("sphere radius = -2"), std::string::npos);
    }
}

}  // namespace
}  // namespace librt
