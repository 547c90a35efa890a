// The chi-square helper is itself checked, or a broken p-value would pass every warp.
#include "sampling/chi_square.h"

#include <gtest/gtest.h>

using namespace librt::testing;

TEST(ChiSquareHelper, PValuesMatchTabulatedQuantiles) {
    // Upper 1% and 5% critical values of the chi-square distribution (standard tables).
    EXPECT_NEAR(chi_square_p_value(6.634897, 1), 0.01, 1e-6);
    EXPECT_NEAR(chi_square_p_value(23.209251, 10), 0.01, 1e-6);
    EXPECT_NEAR(chi_square_p_value(135.806723, 100), 0.01, 1e-6);
    EXPECT_NEAR(chi_square_p_value(124.342113, 100), 0.05, 1e-6);
    EXPECT_NEAR(chi_square_p_value(2.0, 2), std::exp(-1.0), 1e-12);  // Q(1, x) = e^-x
    // Large dof, both branches: the median of chi^2_k is close to k (1 - 2 / (9 k))^3.
    for (const int k : {300, 800, 2000}) {
        const double median = k * std::pow(1.0 - 2.0 / (9.0 * k), 3.0);
        EXPECT_NEAR(chi_square_p_value(median, k), 0.5, 2e-3) << "dof " << k;
    }
}

TEST(ChiSquareHelper, PoolsSmallCellsAndRejectsImpossibleSamples) {
    const ChiSquareResult ok = chi_square_test({100, 98, 2, 1}, {100, 100, 1, 1});
    EXPECT_TRUE(ok.error.empty());
    EXPECT_EQ(ok.pooled_cells, 2);
    EXPECT_EQ(ok.dof, 1);  // the pool (2 expected) joined the smallest regular cell

    const ChiSquareResult bad = chi_square_test({100, 100, 1}, {100, 101, 0});
    EXPECT_FALSE(bad.error.empty());

    const ChiSquareResult skewed = chi_square_test({150, 50}, {100, 100});
    EXPECT_LT(skewed.p_value, 1e-6);
}
