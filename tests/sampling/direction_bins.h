#pragma once

// Binning of unit directions for chi-square tests of direction samplers (warps, light and
// BSDF sampling): equal-solid-angle cells over a band of cos(theta) around a frame's
// normal, and the counts a pdf predicts in each.

#include <librt/sampling/warp.h>

#include <glm/vec3.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

namespace librt::testing {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// Cells over a band of directions: cos(theta) in [cos_lo, cos_hi] around frame.n, split
/// evenly in cos(theta) and phi, so every cell spans the same solid angle.
struct DirectionBins {
    Frame frame;
    double cos_lo = -1.0, cos_hi = 1.0;
    int n_cos = 20, n_phi = 40;

    [[nodiscard]] int size() const { return n_cos * n_phi; }

    /// Cell of a unit world direction, or -1 when outside the band (beyond a rounding slack).
    [[nodiscard]] int cell(const glm::vec3& w) const {
        const glm::vec3 l = frame.to_local(w);
        const double c = l.z;
        constexpr double slack = 1e-5;
        if (!(c >= cos_lo - slack && c <= cos_hi + slack)) return -1;
        const int i =
            std::clamp(static_cast<int>((c - cos_lo) / (cos_hi - cos_lo) * n_cos), 0, n_cos - 1);
        double phi = std::atan2(static_cast<double>(l.y), static_cast<double>(l.x));
        if (phi < 0.0) phi += kTwoPi;
        const int j = std::clamp(static_cast<int>(phi / kTwoPi * n_phi), 0, n_phi - 1);
        return i * n_phi + j;
    }

    /// World direction at (cos(theta), phi).
    [[nodiscard]] glm::vec3 direction(double c, double phi) const {
        const double s = std::sqrt(std::max(0.0, 1.0 - c * c));
        return frame.to_world(glm::vec3(glm::dvec3(s * std::cos(phi), s * std::sin(phi), c)));
    }
};

/// Expected counts n * integral of pdf over each cell (d omega = d cos d phi), by 3-point
/// Gauss-Legendre on 2 x 2 sub-cells: its nodes are interior, so a pdf that drops to 0
/// on a cell edge (a cone's rim) is not sampled on the edge.
inline std::vector<double> expected_counts(const DirectionBins& bins,
                                           const std::function<double(const glm::vec3&)>& pdf,
                                           int n) {
    const std::array<double, 3> node = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    const std::array<double, 3> weight = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    constexpr int sub = 2;
    const double dc = (bins.cos_hi - bins.cos_lo) / (bins.n_cos * sub);
    const double dphi = kTwoPi / (bins.n_phi * sub);
    std::vector<double> expected(static_cast<std::size_t>(bins.size()), 0.0);
    for (int i = 0; i < bins.n_cos * sub; ++i) {
        for (int j = 0; j < bins.n_phi * sub; ++j) {
            double integral = 0.0;
            for (int a = 0; a < 3; ++a) {
                for (int b = 0; b < 3; ++b) {
                    const double c = bins.cos_lo + (i + 0.5 + 0.5 * node[a]) * dc;
                    const double phi = (j + 0.5 + 0.5 * node[b]) * dphi;
                    integral += weight[a] * weight[b] * pdf(bins.direction(c, phi));
                }
            }
            // The weights sum to 2 per axis on [-1, 1]: scale by the half-widths.
            integral *= 0.25 * dc * dphi;
            const auto cell = static_cast<std::size_t>((i / sub) * bins.n_phi + j / sub);
            expected[cell] += n * integral;
        }
    }
    return expected;
}

}  // namespace librt::testing
