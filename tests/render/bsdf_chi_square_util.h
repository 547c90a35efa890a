#pragma once

// Pieces shared by the microfacet tests: the two ends of a BSDF's chi-square test (the
// observed counts of sampled directions per cell, and the test against the expected counts
// that each test integrates its own way), and the directional-albedo bound.

#include "sampling/chi_square.h"
#include "sampling/direction_bins.h"

#include <librt/material/bsdf.h>
#include <librt/material/material.h>
#include <librt/sampling/rng.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

namespace librt::testing {

/// Counts n directions sampled from `material` at wo (numbers from rng) per cell of
/// `bins`, with one last cell for samples that are not valid (absorbed, below the surface).
inline std::vector<double> sampled_direction_counts(const Material& material, const ShadingPoint& p,
                                                    const glm::vec3& wo, const DirectionBins& bins,
                                                    int n, Pcg32& rng) {
    std::vector<double> observed(std::size_t(bins.size()) + 1, 0.0);
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample(material, p, wo, rng.next_float(), rng.next_vec2());
        observed[std::size_t(s.valid() ? bins.cell(s.wi) : bins.size())] += 1.0;
    }
    return observed;
}

/// Expects the chi-square test of observed against expected counts to run and pass at
/// p >= 1e-3 (dozens of cases at fixed seeds: that keeps a false alarm rare across them).
/// A cell the quadrature leaves empty while a rare sample lands there gets a token count
/// of 1e-3, pooled with the other small cells: that a sample is possible at all is
/// checked elsewhere (pdf() > 0 at every sample).
inline void expect_chi_square_passes(const std::vector<double>& observed,
                                     std::vector<double> expected, const std::string& what) {
    for (double& e : expected) e = std::max(e, 1e-3);
    const ChiSquareResult res = chi_square_test(observed, expected);
    EXPECT_TRUE(res.error.empty()) << what << ": " << res.summary();
    EXPECT_GE(res.p_value, 1e-3) << what << ": " << res.summary();
}

/// Expects n directions sampled from `material` at wo (numbers from rng) to follow pdf():
/// the chi-square test of their counts over the whole sphere of directions (frame +z)
/// against pdf()'s quadrature per cell, plus a cell for failed samples holding n minus
/// that integral, which must not exceed n by more than the quadrature's 0.3 %.
inline void expect_sampling_follows_pdf(const Material& material, const ShadingPoint& p,
                                        const glm::vec3& wo, int n, Pcg32& rng,
                                        const std::string& what) {
    DirectionBins sphere;
    sphere.frame = Frame::from_normal({0, 0, 1});
    const std::vector<double> observed = sampled_direction_counts(material, p, wo, sphere, n, rng);
    std::vector<double> expected = expected_counts(
        sphere, [&](const glm::vec3& w) { return double(pdf(material, p, wo, w)); }, n);
    double integral = 0.0;
    for (const double e : expected) integral += e;
    EXPECT_LE(integral, n * 1.003) << what;
    expected.push_back(std::max(0.0, n - integral));
    expect_chi_square_passes(observed, expected, what);
}

/// Expects the directional albedo at wo, the mean of n sampled weights f cos / pdf (numbers
/// from rng), to be at most 1 per channel within 4 standard errors.
inline void expect_albedo_at_most_one(const Material& material, const ShadingPoint& p,
                                      const glm::vec3& wo, int n, Pcg32& rng,
                                      const std::string& what) {
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int i = 0; i < n; ++i) {
        const BsdfSample s = sample(material, p, wo, rng.next_float(), rng.next_vec2());
        if (!s.valid()) continue;
        sum += glm::dvec3(s.weight);
        sum2 += glm::dvec3(s.weight) * glm::dvec3(s.weight);
    }
    for (int k = 0; k < 3; ++k) {
        const double mean = sum[k] / n;
        const double se = std::sqrt(std::max(0.0, sum2[k] / n - mean * mean) / n);
        EXPECT_LE(mean, 1.0 + 4.0 * se) << what << ", channel " << k;
    }
}

/// Whether sample s drawn at wo agrees with the BSDF's other functions: its lobe is one of
/// the material's, its pdf is pdf() (relative 1e-4), f = eval() >= 0 and its weight is
/// f |cos| / pdf (relative 2e-3).
inline ::testing::AssertionResult sample_agrees_with_eval_pdf(const Material& material,
                                                              const ShadingPoint& p,
                                                              const glm::vec3& wo,
                                                              const BsdfSample& s) {
    if (!has(lobes(material), s.lobe)) return ::testing::AssertionFailure() << "foreign lobe";
    const glm::vec3 f = eval(material, p, wo, s.wi);
    const float d = pdf(material, p, wo, s.wi);
    if (!(std::fabs(s.pdf - d) <= 1e-4f * d))
        return ::testing::AssertionFailure() << "sample pdf " << s.pdf << ", pdf() " << d;
    for (int k = 0; k < 3; ++k) {
        if (!(f[k] >= 0.0f)) return ::testing::AssertionFailure() << "f[" << k << "] = " << f[k];
        const float expected = f[k] * std::fabs(s.wi.z) / d;
        if (!(std::fabs(s.weight[k] - expected) <= 2e-3f * expected + 1e-6f))
            return ::testing::AssertionFailure()
                   << "weight[" << k << "] = " << s.weight[k] << ", f cos / pdf " << expected;
    }
    return ::testing::AssertionSuccess();
}

}  // namespace librt::testing
