// Spherical-triangle sampling (Arvo 1995): the solid angle against closed forms and its
// own additivity, and a chi-square test of the sampled directions against the uniform
// density 1 / omega, binned over a subdivision of the triangle whose cells' probabilities
// are their exact solid angles.

#include "sampling/spherical_triangle.h"

#include "chi_square.h"

#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <cmath>
#include <numbers>
#include <vector>

namespace librt {
namespace {

using testing::chi_square_test;

glm::vec3 dir(float x, float y, float z) { return glm::normalize(glm::vec3(x, y, z)); }

TEST(SphericalTriangle, OctantIsHalfPi) {
    // The triangle of the three axes covers 1/8 of the sphere: 4 pi / 8.
    EXPECT_NEAR(spherical_triangle_solid_angle({1, 0, 0}, {0, 1, 0}, {0, 0, 1}),
                0.5 * std::numbers::pi, 1e-6);
}

TEST(SphericalTriangle, SmallFarTriangleIsAreaTimesCosOverDistanceSquared) {
    // A triangle of area A at distance d facing the origin: omega -> A / d^2 as A / d^2 -> 0.
    const float d = 50.0f;
    const glm::vec3 p0{0, 0, d}, p1{0.1f, 0, d}, p2{0, 0.1f, d};
    const double area = 0.5 * 0.1 * 0.1;
    const double omega =
        spherical_triangle_solid_angle(glm::normalize(p0), glm::normalize(p1), glm::normalize(p2));
    EXPECT_NEAR(omega / (area / (double(d) * d)), 1.0, 1e-3);
}

TEST(SphericalTriangle, SolidAngleIsAdditiveOverASubdivision) {
    const glm::vec3 a = dir(1, 0.1f, 0.2f), b = dir(-0.3f, 1, 0.1f), c = dir(0.2f, -0.1f, 1);
    const glm::vec3 ab = glm::normalize(a + b), bc = glm::normalize(b + c),
                    ca = glm::normalize(c + a);
    const double whole = spherical_triangle_solid_angle(a, b, c);
    const double parts = double(spherical_triangle_solid_angle(a, ab, ca)) +
                         spherical_triangle_solid_angle(ab, b, bc) +
                         spherical_triangle_solid_angle(ca, bc, c) +
                         spherical_triangle_solid_angle(ab, bc, ca);
    EXPECT_NEAR(parts, whole, 1e-5 * whole);
}

// Chi-square of n samples over the n_sub^2 cells of the regular subdivision of the flat
// triangle p0 p1 p2 (seen from the origin), each expecting n omega_cell / omega.
void expect_uniform_over(const glm::vec3& p0, const glm::vec3& p1, const glm::vec3& p2,
                         const char* what) {
    constexpr int n_sub = 8, count = 200000;
    const glm::dvec3 q0(p0), e1 = glm::dvec3(p1) - q0, e2 = glm::dvec3(p2) - q0;
    const glm::dvec3 nrm = glm::cross(e1, e2);
    auto corner = [&](int i, int j) {
        return glm::vec3(glm::normalize(q0 + (double(i) / n_sub) * e1 + (double(j) / n_sub) * e2));
    };
    // Cell index: "up" cells (i, j), i + j < n_sub, then "down" cells (i, j), i + j < n_sub - 1.
    std::vector<double> expected, observed;
    std::vector<int> up(n_sub * n_sub, -1), down(n_sub * n_sub, -1);
    const double omega =
        spherical_triangle_solid_angle(glm::normalize(p0), glm::normalize(p1), glm::normalize(p2));
    ASSERT_GT(omega, 0.0);
    for (int i = 0; i < n_sub; ++i)
        for (int j = 0; i + j < n_sub; ++j) {
            up[i * n_sub + j] = int(expected.size());
            expected.push_back(
                count *
                spherical_triangle_solid_angle(corner(i, j), corner(i + 1, j), corner(i, j + 1)) /
                omega);
            if (i + j < n_sub - 1) {
                down[i * n_sub + j] = int(expected.size());
                expected.push_back(count *
                                   spherical_triangle_solid_angle(
                                       corner(i + 1, j), corner(i + 1, j + 1), corner(i, j + 1)) /
                                   omega);
            }
        }
    observed.assign(expected.size(), 0.0);
    Pcg32 rng(17, 3);
    int outside = 0;
    for (int k = 0; k < count; ++k) {
        const SphericalTriangleSample s =
            sample_spherical_triangle(glm::normalize(p0), glm::normalize(p1), glm::normalize(p2),
                                      float(omega), {rng.next_float(), rng.next_float()});
        ASSERT_NEAR(s.solid_angle, omega, 1e-6 * omega + 1e-9);
        ASSERT_NEAR(glm::length(s.direction), 1.0f, 1e-5f);
        // Where the direction meets the triangle's plane, in barycentrics (b1, b2).
        const glm::dvec3 w(s.direction);
        const double t = glm::dot(q0, nrm) / glm::dot(w, nrm);
        const glm::dvec3 q = t * w - q0;
        const double nn = glm::dot(nrm, nrm);
        const double b1 = glm::dot(glm::cross(q, e2), nrm) / nn;
        const double b2 = glm::dot(glm::cross(e1, q), nrm) / nn;
        const double eps = 1e-5;
        if (!(t > 0.0) || b1 < -eps || b2 < -eps || b1 + b2 > 1.0 + eps) {
            ++outside;
            continue;
        }
        const double x = std::clamp(b1, 0.0, 1.0 - 1e-12) * n_sub;
        const double y = std::clamp(b2, 0.0, 1.0 - 1e-12) * n_sub;
        int i = int(x), j = int(y);
        if (i + j > n_sub - 1) {  // rounding past the long edge: the last up cell of the row
            j = n_sub - 1 - i;
            observed[std::size_t(up[i * n_sub + j])] += 1.0;
            continue;
        }
        const bool is_up = (x - i) + (y - j) < 1.0;
        const int cell = is_up ? up[i * n_sub + j] : down[i * n_sub + j];
        observed[std::size_t(cell >= 0 ? cell : up[i * n_sub + j])] += 1.0;
    }
    EXPECT_EQ(outside, 0) << what << ": samples outside the triangle";
    const auto r = chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << what << ": " << r.summary();
    EXPECT_GE(r.p_value, 1e-3) << what << ": " << r.summary();
}

TEST(SphericalTriangle, SamplesAreUniformOverTheSolidAngle) {
    expect_uniform_over({1, 0, 0}, {0, 1, 0}, {0, 0, 1}, "octant");
    expect_uniform_over({-1, -1, 0.02f}, {1, -1, 0.02f}, {0, 1, 0.02f}, "near (omega ~ 2 pi)");
    expect_uniform_over({-0.3f, 0.2f, 2}, {2.5f, 0.1f, 1}, {0.1f, 0.25f, 3}, "thin sliver");
    expect_uniform_over({0, 0, 5}, {0.1f, 0, 5}, {0, 0.1f, 5.1f}, "small and far");
}

TEST(SphericalTriangle, DegenerateTriangleGivesNoSample) {
    // Three directions in one great circle (z = 0): no solid angle, no sample.
    const glm::vec3 a{1, 0, 0}, b{0, 1, 0}, c{0.6f, 0.8f, 0};
    const float omega = spherical_triangle_solid_angle(a, b, c);
    EXPECT_EQ(omega, 0.0f);
    EXPECT_EQ(sample_spherical_triangle(a, b, c, omega, {0.5f, 0.5f}).solid_angle, 0.0f);
}

}  // namespace
}  // namespace librt
