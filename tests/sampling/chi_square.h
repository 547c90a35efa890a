#pragma once

// Pearson's chi-square goodness-of-fit test for the sampling tests: the observed counts
// of a sampler in some cells against the counts its pdf predicts.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

namespace librt::testing {

/// Regularized upper incomplete gamma Q(a, x) = Gamma(a, x) / Gamma(a), a > 0, x >= 0.
inline double regularized_gamma_q(double a, double x) {
    if (x <= 0.0) return 1.0;
    // Common factor e^-x x^a / Gamma(a), in logs to survive a, x ~ 1000.
    const double log_prefix = -x + a * std::log(x) - std::lgamma(a);
    constexpr double eps = 1e-15;
    constexpr int max_iter = 100000;
    if (x < a + 1.0) {
        // Series P(a, x) = prefix / a * sum_n x^n / ((a + 1) ... (a + n)); Q = 1 - P.
        double term = 1.0 / a, sum = term;
        for (int n = 1; n < max_iter && std::abs(term) > eps * std::abs(sum); ++n) {
            term *= x / (a + n);
            sum += term;
        }
        return std::max(0.0, 1.0 - sum * std::exp(log_prefix));
    }
    // Continued fraction Q(a, x) = prefix / (x + 1 - a - 1 (1 - a) / (x + 3 - a - ...)),
    // evaluated by the modified Lentz method.
    constexpr double tiny = 1e-300;
    double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
    for (int i = 1; i < max_iter; ++i) {
        const double an = -i * (i - a);
        b += 2.0;
        d = an * d + b;
        if (std::abs(d) < tiny) d = tiny;
        c = b + an / c;
        if (std::abs(c) < tiny) c = tiny;
        d = 1.0 / d;
        const double delta = d * c;
        h *= delta;
        if (std::abs(delta - 1.0) < eps) break;
    }
    return std::exp(log_prefix) * h;
}

/// P(X >= statistic) for X chi-square distributed with dof degrees of freedom.
inline double chi_square_p_value(double statistic, int dof) {
    return regularized_gamma_q(0.5 * dof, 0.5 * statistic);
}

/// Outcome of chi_square_test; passes when error is empty and p_value >= the significance.
struct ChiSquareResult {
    double statistic = 0.0;
    int dof = 0;
    double p_value = 0.0;
    int pooled_cells = 0;  ///< cells with a too small expected count, merged into one
    std::string error;     ///< set when the test cannot even be run (e.g. impossible samples)

    /// One line for test failure messages.
    std::string summary() const {
        std::ostringstream s;
        s << "chi^2 = " << statistic << ", dof = " << dof << ", p = " << p_value << ", pooled "
          << pooled_cells << " cells" << (error.empty() ? "" : ", error: ") << error;
        return s.str();
    }
};

/// Chi-square test of observed against expected counts. Cells expecting fewer than
/// min_expected samples are pooled (the chi-square approximation needs ~5 per cell); a
/// pool still below it joins the smallest regular cell. A sample in a cell expecting
/// exactly zero is an error. dof = cells used - 1 (the total is fixed by the sample count).
inline ChiSquareResult chi_square_test(const std::vector<double>& observed,
                                       const std::vector<double>& expected,
                                       double min_expected = 5.0) {
    ChiSquareResult result;
    if (observed.size() != expected.size()) {
        result.error = "observed and expected differ in size";
        return result;
    }
    std::vector<std::size_t> order(observed.size());
    std::iota(order.begin(), order.end(), std::size_t{0});
    std::sort(order.begin(), order.end(),
              [&](std::size_t i, std::size_t j) { return expected[i] < expected[j]; });

    double pool_obs = 0.0, pool_exp = 0.0;
    std::vector<std::pair<double, double>> cells;  // (observed, expected), ascending expected
    for (const std::size_t i : order) {
        if (expected[i] <= 0.0) {
            if (observed[i] > 0.0) {
                std::ostringstream s;
                s << observed[i] << " samples in cell " << i << ", which expects none";
                result.error = s.str();
                return result;
            }
        } else if (expected[i] < min_expected) {
            pool_obs += observed[i];
            pool_exp += expected[i];
            ++result.pooled_cells;
        } else {
            cells.emplace_back(observed[i], expected[i]);
        }
    }
    if (pool_exp >= min_expected || (pool_exp > 0.0 && cells.empty())) {
        cells.emplace_back(pool_obs, pool_exp);
    } else if (pool_exp > 0.0) {
        cells.front().first += pool_obs;
        cells.front().second += pool_exp;
    }
    if (cells.size() < 2) {
        result.error = "fewer than two usable cells";
        return result;
    }
    for (const auto& [obs, exp] : cells) result.statistic += (obs - exp) * (obs - exp) / exp;
    result.dof = static_cast<int>(cells.size()) - 1;
    result.p_value = chi_square_p_value(result.statistic, result.dof);
    return result;
}

}  // namespace librt::testing
