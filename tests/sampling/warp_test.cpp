#include "sampling/chi_square.h"
#include "sampling/direction_bins.h"

#include <librt/sampling/rng.h>
#include <librt/sampling/warp.h>

#include <gtest/gtest.h>

#include <glm/geometric.hpp>

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

using namespace librt;
using librt::testing::chi_square_test;
using librt::testing::ChiSquareResult;
using librt::testing::DirectionBins;
using librt::testing::expected_counts;

namespace {

constexpr double kSignificance = 0.01;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Runs the full test: n directions from sample(u), binned and compared with the pdf.
void expect_directions_follow_pdf(const DirectionBins& bins,
                                  const std::function<glm::vec3(glm::vec2)>& sample,
                                  const std::function<double(const glm::vec3&)>& pdf,
                                  std::uint64_t seed, int n = 200'000) {
    Pcg32 rng(seed, 1u);
    std::vector<double> observed(static_cast<std::size_t>(bins.size()), 0.0);
    int outside = 0;
    for (int k = 0; k < n; ++k) {
        const int cell = bins.cell(glm::normalize(sample(rng.next_vec2())));
        if (cell < 0) {
            ++outside;
        } else {
            observed[static_cast<std::size_t>(cell)] += 1.0;
        }
    }
    EXPECT_EQ(outside, 0) << "samples outside the band the pdf covers";
    const std::vector<double> expected = expected_counts(bins, pdf, n);
    // The pdf must integrate to 1 over the band (cells are smooth, the quadrature is
    // near-exact), so the expected counts must add up to n.
    double total = 0.0;
    for (const double e : expected) total += e;
    EXPECT_NEAR(total / n, 1.0, 1e-3);
    const ChiSquareResult r = chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.summary();
    EXPECT_GE(r.p_value, kSignificance) << r.summary();
}

/// The cone of half-angle theta_max a sphere subtends at ref, in double.
double cos_theta_max(const glm::vec3& center, float radius, const glm::vec3& ref) {
    const glm::dvec3 v = glm::dvec3(center) - glm::dvec3(ref);
    const double sin2 = double(radius) * radius / glm::dot(v, v);
    return std::sqrt(1.0 - sin2);
}

glm::vec3 normalized_axis(const glm::vec3& from, const glm::vec3& to) {
    return glm::normalize(to - from);
}

}  // namespace

// ---- Frame ---------------------------------------------------------------------------

TEST(Frame, OrthonormalAndRightHandedForManyNormals) {
    std::vector<glm::vec3> normals = {{0, 0, 1},
                                      {0, 0, -1},
                                      {1, 0, 0},
                                      {0, 1, 0},
                                      {-1, 0, 0},
                                      {0, -1, 0},
                                      glm::normalize(glm::vec3(1e-7f, 0, -1)),
                                      glm::normalize(glm::vec3(0, 1e-4f, -1)),
                                      glm::normalize(glm::vec3(1e-4f, -1e-4f, -1)),
                                      glm::normalize(glm::vec3(1e-3f, 1e-3f, -1)),
                                      glm::normalize(glm::vec3(1, 1, -1e-7f)),
                                      glm::normalize(glm::vec3(1, -1, 1e-7f)),
                                      glm::normalize(glm::vec3(-3e-4f, 2e-4f, 1))};
    Pcg32 rng(11u, 0u);
    for (int i = 0; i < 10'000; ++i) normals.push_back(sample_uniform_sphere(rng.next_vec2()));

    constexpr float tol = 1e-5f;
    for (const glm::vec3& n : normals) {
        const Frame f = Frame::from_normal(n);
        SCOPED_TRACE(::testing::Message() << "n = (" << n.x << ", " << n.y << ", " << n.z << ")");
        EXPECT_NEAR(glm::length(f.t), 1.0f, tol);
        EXPECT_NEAR(glm::length(f.b), 1.0f, tol);
        EXPECT_NEAR(glm::dot(f.t, f.b), 0.0f, tol);
        EXPECT_NEAR(glm::dot(f.t, f.n), 0.0f, tol);
        EXPECT_NEAR(glm::dot(f.b, f.n), 0.0f, tol);
        EXPECT_LT(glm::length(glm::cross(f.t, f.b) - n), tol);
        const glm::vec3 v(0.3f, -0.5f, 0.8f);
        EXPECT_LT(glm::length(f.to_local(f.to_world(v)) - v), tol);
        EXPECT_LT(glm::length(f.to_world(glm::vec3(0, 0, 1)) - n), tol);
        ASSERT_TRUE(std::isfinite(f.t.x + f.t.y + f.t.z + f.b.x + f.b.y + f.b.z));
    }
}

// ---- Direction warps against their pdfs ------------------------------------------------

TEST(Warp, CosineHemisphereChiSquare) {
    DirectionBins bins;
    bins.cos_lo = 0.0;
    expect_directions_follow_pdf(
        bins, [](glm::vec2 u) { return sample_cosine_hemisphere(u); },
        [](const glm::vec3& w) { return double(cosine_hemisphere_pdf(w.z)); }, 101);
}

TEST(Warp, CosineHemisphereAroundNormalChiSquare) {
    const glm::vec3 normal = glm::normalize(glm::vec3(-0.3f, 0.8f, -0.5f));
    DirectionBins bins;
    bins.frame = Frame::from_normal(normal);
    bins.cos_lo = 0.0;
    expect_directions_follow_pdf(
        bins, [&](glm::vec2 u) { return sample_cosine_hemisphere(normal, u); },
        [&](const glm::vec3& w) { return double(cosine_hemisphere_pdf(glm::dot(normal, w))); },
        102);
}

TEST(Warp, CosineHemisphereIsTheReportFormula) {
    const glm::vec2 u(0.125f, 0.36f);
    const glm::vec3 w = sample_cosine_hemisphere(u);
    EXPECT_NEAR(w.x, std::cos(std::numbers::pi_v<float> / 4) * 0.8f, 1e-6f);
    EXPECT_NEAR(w.y, std::sin(std::numbers::pi_v<float> / 4) * 0.8f, 1e-6f);
    EXPECT_NEAR(w.z, 0.6f, 1e-6f);
    EXPECT_EQ(cosine_hemisphere_pdf(-0.1f), 0.0f);
    EXPECT_FLOAT_EQ(cosine_hemisphere_pdf(1.0f), std::numbers::inv_pi_v<float>);
}

TEST(Warp, UniformSphereChiSquare) {
    expect_directions_follow_pdf(
        DirectionBins{}, [](glm::vec2 u) { return sample_uniform_sphere(u); },
        [](const glm::vec3&) { return double(uniform_sphere_pdf()); }, 103);
}

TEST(Warp, UniformHemisphereChiSquare) {
    DirectionBins bins;
    bins.cos_lo = 0.0;
    expect_directions_follow_pdf(
        bins, [](glm::vec2 u) { return sample_uniform_hemisphere(u); },
        [](const glm::vec3&) { return double(uniform_hemisphere_pdf()); }, 104);
}

TEST(Warp, UniformConeChiSquare) {
    // Distinct seeds: cos(theta) is linear in u, so one seed would bin all cones alike.
    const std::array<float, 3> cones = {0.6f, -0.3f, 0.98f};
    for (std::size_t k = 0; k < cones.size(); ++k) {
        const float cos_max = cones[k];
        SCOPED_TRACE(::testing::Message() << "cos_theta_max = " << cos_max);
        DirectionBins bins;
        bins.cos_lo = cos_max;
        expect_directions_follow_pdf(
            bins, [&](glm::vec2 u) { return sample_uniform_cone(u, cos_max); },
            [&](const glm::vec3& w) {
                return w.z >= cos_max ? double(uniform_cone_pdf(cos_max)) : 0.0;
            },
            105 + 16 * k);
    }
}

// ---- Disk and triangle ------------------------------------------------------------------

TEST(Warp, ConcentricDiskInsideAndAreaUniform) {
    // Rings of equal area (r^2 uniform) times equal sectors: every cell expects n / cells.
    constexpr int n = 100'000, rings = 10, sectors = 16;
    Pcg32 rng(106u, 1u);
    std::vector<double> observed(rings * sectors, 0.0);
    for (int k = 0; k < n; ++k) {
        const glm::vec2 p = sample_uniform_disk_concentric(rng.next_vec2());
        const double r2 = double(p.x) * p.x + double(p.y) * p.y;
        ASSERT_LE(r2, 1.0 + 1e-6);
        double phi = std::atan2(double(p.y), double(p.x));
        if (phi < 0.0) phi += kTwoPi;
        const int i = std::min(static_cast<int>(r2 * rings), rings - 1);
        const int j = std::min(static_cast<int>(phi / kTwoPi * sectors), sectors - 1);
        observed[static_cast<std::size_t>(i * sectors + j)] += 1.0;
    }
    const std::vector<double> expected(rings * sectors, double(n) / (rings * sectors));
    const ChiSquareResult r = chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.summary();
    EXPECT_GE(r.p_value, kSignificance) << r.summary();
    EXPECT_FLOAT_EQ(uniform_disk_pdf(), std::numbers::inv_pi_v<float>);
}

TEST(Warp, ConcentricDiskMapsCentreAndBoundary) {
    EXPECT_EQ(sample_uniform_disk_concentric({0.5f, 0.5f}), glm::vec2(0.0f));
    for (const glm::vec2 u :
         {glm::vec2(0, 0), glm::vec2(0, 0.5f), glm::vec2(0.25f, 0), glm::vec2(0, 0.9f)}) {
        EXPECT_NEAR(glm::length(sample_uniform_disk_concentric(u)), 1.0f, 1e-6f);
    }
}

TEST(Warp, TriangleBarycentricsUniform) {
    // Split the triangle into k^2 congruent triangles (equal areas): cell (i, j) is the
    // parallelogram [i, i+1) x [j, j+1) of (k u, k v), lower or upper half.
    constexpr int n = 100'000, k = 10;
    Pcg32 rng(107u, 1u);
    std::vector<double> observed(k * k, 0.0);
    double sum_u = 0.0, sum_v = 0.0;
    for (int s = 0; s < n; ++s) {
        const glm::vec2 b = sample_uniform_triangle(rng.next_vec2());
        ASSERT_GE(b.x, 0.0f);
        ASSERT_GE(b.y, 0.0f);
        ASSERT_LE(b.x + b.y, 1.0f + 1e-6f);
        sum_u += b.x;
        sum_v += b.y;
        const double x = b.x * double(k), y = b.y * double(k);
        const int i = std::min(static_cast<int>(x), k - 1);
        const int j = std::min(static_cast<int>(y), k - 1);
        const bool upper = (x - i) + (y - j) >= 1.0;
        // Row i holds 2 (k - i) - 1 cells: lower halves for j < k - i, upper for j < k - i - 1.
        int cell = 0;
        for (int r = 0; r < i; ++r) cell += 2 * (k - r) - 1;
        cell += upper ? (k - i) + j : j;
        observed[static_cast<std::size_t>(std::min(cell, k * k - 1))] += 1.0;
    }
    const std::vector<double> expected(k * k, double(n) / (k * k));
    const ChiSquareResult r = chi_square_test(observed, expected);
    EXPECT_GE(r.p_value, kSignificance) << r.summary();
    // Each barycentric is Beta(1, 2): mean 1/3, variance 1/18.
    const double tol = 5.0 * std::sqrt(1.0 / 18.0 / n);
    EXPECT_NEAR(sum_u / n, 1.0 / 3.0, tol);
    EXPECT_NEAR(sum_v / n, 1.0 / 3.0, tol);
}

// ---- Sphere lights ----------------------------------------------------------------------

TEST(SphereLight, AreaSamplesLieOnSphereWithAreaPdf) {
    const glm::vec3 c(1, -2, 3);
    const float r = 2.5f;
    Pcg32 rng(108u, 1u);
    for (int k = 0; k < 10'000; ++k) {
        const SphereSample s = sample_sphere_area(c, r, rng.next_vec2());
        ASSERT_NEAR(glm::length(s.point - c), r, 1e-5f);
        ASSERT_LT(glm::length(s.normal - (s.point - c) / r), 1e-5f);
        ASSERT_FLOAT_EQ(s.pdf, 1.0f / (4.0f * std::numbers::pi_v<float> * r * r));
    }
}

TEST(SphereLight, VisibleDirectionsChiSquare) {
    // A moderate cone (d = 2.8 r, theta_max = 21 deg) and a wide one (d = 1.1 r, 65 deg).
    struct Setup {
        glm::vec3 c, ref;
        float d_over_r;
    };
    const std::array<Setup, 2> setups = {
        {{{2, -1, 3}, {0.5f, 0.2f, -0.4f}, 2.8f}, {{0, 0, 0}, {0.9f, -1.3f, 0.7f}, 1.1f}}};
    for (std::size_t k = 0; k < setups.size(); ++k) {
        const glm::vec3 c = setups[k].c, ref = setups[k].ref;
        const float r = glm::length(ref - c) / setups[k].d_over_r;
        SCOPED_TRACE(::testing::Message() << "setup " << k);
        DirectionBins bins;
        bins.frame = Frame::from_normal(normalized_axis(ref, c));
        bins.cos_lo = cos_theta_max(c, r, ref);
        expect_directions_follow_pdf(
            bins, [&](glm::vec2 u) { return sample_sphere_visible(c, r, ref, u).point - ref; },
            [&](const glm::vec3& w) { return double(sphere_visible_pdf(c, r, ref, w)); }, 109 + k);
    }
}

TEST(SphereLight, InsideDirectionsChiSquare) {
    // From inside, every direction hits the sphere once; the area fallback's density.
    const glm::vec3 c(0.5f, 1, -1), ref(0.5f, 1.6f, -0.7f);
    const float r = 1.0f;
    expect_directions_follow_pdf(
        DirectionBins{},
        [&](glm::vec2 u) { return sample_sphere_visible(c, r, ref, u).point - ref; },
        [&](const glm::vec3& w) { return double(sphere_visible_pdf(c, r, ref, w)); }, 111);
}

TEST(SphereLight, VisiblePointsOnSphereFacingRefWithMatchingPdf) {
    const glm::vec3 c(2, -1, 3), ref(0.5f, 0.2f, -0.4f);
    const float r = 1.4f;
    const double expected_pdf = 1.0 / (kTwoPi * (1.0 - cos_theta_max(c, r, ref)));
    Pcg32 rng(112u, 1u);
    for (int k = 0; k < 20'000; ++k) {
        const glm::vec2 u = rng.next_vec2();
        const SphereSample s = sample_sphere_visible(c, r, ref, u);
        ASSERT_NEAR(glm::length(s.point - c), r, 1e-5f);
        ASSERT_NEAR(glm::length(s.normal), 1.0f, 1e-5f);
        ASSERT_LT(glm::length(s.normal - (s.point - c) / r), 1e-5f);
        ASSERT_GE(glm::dot(s.normal, ref - s.point), -1e-4f) << "point hidden from ref";
        ASSERT_NEAR(s.pdf, expected_pdf, 1e-5 * expected_pdf);
        // Away from the silhouette (where a rounded direction may just miss), the pdf
        // function agrees with the sampler.
        if (u.x < 0.99f) {
            const glm::vec3 wi = glm::normalize(s.point - ref);
            ASSERT_FLOAT_EQ(sphere_visible_pdf(c, r, ref, wi), s.pdf);
        }
    }
}

TEST(SphereLight, DirectionSamplesAreTheVisiblePointsSeenFromRef) {
    // sample_sphere_direction must pick, for the same u, the direction toward
    // sample_sphere_visible's point, at its distance and with its pdf: from near (wide cone),
    // far (tiny cone) and inside the sphere.
    struct Case {
        glm::vec3 c, ref;
        float r;
    };
    const std::array<Case, 4> cases = {{{{2, -1, 3}, {0.5f, 0.2f, -0.4f}, 1.4f},
                                        {{0, 0, 0}, {0, 0.3f, 1.05f}, 1.0f},
                                        {{-10, 20, 40}, {3e3f, -1e3f, 2e3f}, 10.0f},
                                        {{0, 0, 0}, {0.3f, -0.2f, 0.5f}, 1.0f}}};
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const Case& cs = cases[k];
        SCOPED_TRACE(::testing::Message() << "case " << k);
        Pcg32 rng(130u + k, 1u);
        for (int i = 0; i < 20'000; ++i) {
            const glm::vec2 u = rng.next_vec2();
            const SphereSample p = sample_sphere_visible(cs.c, cs.r, cs.ref, u);
            const SphereDirectionSample d = sample_sphere_direction(cs.c, cs.r, cs.ref, u);
            const float expected_distance = glm::length(p.point - cs.ref);
            ASSERT_NEAR(glm::length(d.direction), 1.0f, 1e-6f);
            ASSERT_NEAR(d.distance, expected_distance, 2e-6f * expected_distance + 1e-5f * cs.r);
            // Relative to r, and to the float spacing where the points lie (~1 ulp of the
            // far case's 3.7e3 units: a 1e-7 rad turn of the direction moves it 4e-4).
            const float tolerance = 2e-5f * cs.r + 1e-7f * (glm::length(cs.ref) + d.distance);
            ASSERT_LT(glm::length(cs.ref + d.distance * d.direction - p.point), tolerance)
                << "u = (" << u.x << ", " << u.y << ")";
            ASSERT_FLOAT_EQ(d.pdf, p.pdf);
        }
    }
}

TEST(SphereLight, DirectionSamplesFollowTheVisiblePdf) {
    const glm::vec3 c(2, -1, 3), ref(0.5f, 0.2f, -0.4f);
    const float r = glm::length(ref - c) / 1.1f;  // a wide cone, 65 degrees
    DirectionBins bins;
    bins.frame = Frame::from_normal(normalized_axis(ref, c));
    bins.cos_lo = cos_theta_max(c, r, ref);
    expect_directions_follow_pdf(
        bins, [&](glm::vec2 u) { return sample_sphere_direction(c, r, ref, u).direction; },
        [&](const glm::vec3& w) { return double(sphere_visible_pdf(c, r, ref, w)); }, 131);
}

TEST(SphereLight, InsidePdfMatchesFunctionAndIsFinite) {
    const glm::vec3 c(0, 0, 0), ref(0.3f, -0.2f, 0.5f);
    const float r = 1.0f;
    Pcg32 rng(113u, 1u);
    for (int k = 0; k < 20'000; ++k) {
        const SphereSample s = sample_sphere_visible(c, r, ref, rng.next_vec2());
        ASSERT_NEAR(glm::length(s.point - c), r, 1e-5f);
        ASSERT_TRUE(std::isfinite(s.pdf));
        ASSERT_GT(s.pdf, 0.0f);
        const glm::vec3 wi = glm::normalize(s.point - ref);
        ASSERT_NEAR(sphere_visible_pdf(c, r, ref, wi), s.pdf, 1e-3f * s.pdf);
    }
}

TEST(SphereLight, VisiblePdfIntegratesToOne) {
    // Monte Carlo over directions: E[pdf(w) / q(w)] = integral of pdf = 1 for w ~ q.
    // Outside, q is uniform on the hemisphere facing the sphere (the cone lies in it);
    // inside, uniform on the sphere. Tolerance: 5 standard errors from the samples.
    struct Case {
        glm::vec3 c, ref;
        float r;
    };
    const std::array<Case, 3> cases = {{{{2, -1, 3}, {0.5f, 0.2f, -0.4f}, 1.4f},
                                        {{0, 0, 0}, {0, 0, 1.02f}, 1.0f},
                                        {{0, 0, 0}, {0.3f, -0.2f, 0.5f}, 1.0f}}};
    constexpr int n = 200'000;
    for (std::size_t k = 0; k < cases.size(); ++k) {
        const Case& cs = cases[k];
        const bool inside = glm::length(cs.ref - cs.c) < cs.r;
        const Frame frame = Frame::from_normal(normalized_axis(cs.ref, cs.c));
        Pcg32 rng(114u + k, 1u);
        double sum = 0.0, sum2 = 0.0;
        for (int s = 0; s < n; ++s) {
            const glm::vec2 u = rng.next_vec2();
            const glm::vec3 w =
                inside ? sample_uniform_sphere(u) : frame.to_world(sample_uniform_hemisphere(u));
            const double q = inside ? uniform_sphere_pdf() : uniform_hemisphere_pdf();
            const double x = sphere_visible_pdf(cs.c, cs.r, cs.ref, w) / q;
            sum += x;
            sum2 += x * x;
        }
        const double mean = sum / n;
        const double std_error = std::sqrt((sum2 / n - mean * mean) / n);
        EXPECT_NEAR(mean, 1.0, 5.0 * std_error) << "case " << k;
    }
}

TEST(SphereLight, TinyConesKeepTheirPdfAndShape) {
    // A unit sphere seen from d = 2 ... 1e5: (1 - cos theta_max) ~ 1 / (2 d^2) is far below
    // float's epsilon at 1e4, where 1 - cos in float would be 0 and the pdf infinite.
    const glm::vec3 ref(0.0f);
    for (const float d : {2.0f, 1e2f, 1e3f, 1e4f, 1e5f}) {
        SCOPED_TRACE(::testing::Message() << "d = " << d);
        const glm::vec3 c(0, 0, d);
        const float r = 1.0f;
        const double sin2 = 1.0 / (double(d) * d);
        const double one_minus_cos = sin2 / (1.0 + std::sqrt(1.0 - sin2));
        const double expected_pdf = 1.0 / (kTwoPi * one_minus_cos);
        EXPECT_NEAR(sphere_visible_pdf(c, r, ref, {0, 0, 1}), expected_pdf, 1e-5 * expected_pdf);

        // sin^2(theta) / sin^2(theta_max) is uniform on [0, 1] for a uniform cone (exactly
        // 1 - cos is uniform; sin^2 = (1 - cos)(1 + cos) bends it by < sin^2(theta_max)).
        constexpr int n = 50'000;
        Pcg32 rng(120u, 1u);
        double sum = 0.0;
        for (int k = 0; k < n; ++k) {
            const SphereSample s = sample_sphere_visible(c, r, ref, rng.next_vec2());
            ASSERT_NEAR(s.pdf, expected_pdf, 1e-5 * expected_pdf);
            const glm::dvec3 p(s.point);
            ASSERT_NEAR(glm::length(p - glm::dvec3(c)), r, 8.0 * 1.2e-7 * (d + r));
            ASSERT_GE(glm::dot(glm::dvec3(s.normal), glm::dvec3(ref) - p), -1e-3 * d);
            const double q = (p.x * p.x + p.y * p.y) / glm::dot(p, p) / sin2;
            ASSERT_LE(q, 1.0 + 1e-3);
            sum += q;
        }
        EXPECT_NEAR(sum / n, 0.5, 5.0 * std::sqrt(1.0 / 12.0 / n) + sin2);
    }
}
