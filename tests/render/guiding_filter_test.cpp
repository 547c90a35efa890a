// The SD-tree's record filtering (GuidingSettings::filter_records, a stochastic box filter
// in space and direction): what every leaf learns is still a normalised density that its
// sampler follows (chi-square of samples against pdf), records reach the neighbours of
// their leaf, and the learned tree does not depend on the order records arrive in.

#include "integrator/guiding/quad_tree.h"
#include "integrator/guiding/sd_tree.h"
#include "sampling/chi_square.h"

#include <librt/geometry/bbox.h>
#include <librt/integrator/guiding.h>
#include <librt/sampling/rng.h>
#include <librt/sampling/warp.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <vector>

namespace librt {
namespace {

using guiding::QuadTree;
using guiding::SdTree;

struct Record {
    glm::vec3 p, dir;
    float flux;
};

/// Records of a field whose incident light comes from around `axis` (a cosine-power lobe
/// of exponent 50, plus 20% uniform), at points uniform in the unit cube.
std::vector<Record> lobe_records(std::uint64_t seed, int count) {
    Pcg32 rng(seed, 3);
    const glm::vec3 axis = glm::normalize(glm::vec3(-0.2f, 0.7f, 0.4f));
    std::vector<Record> out;
    for (int i = 0; i < count; ++i) {
        const glm::vec3 p(rng.next_float(), rng.next_float(), rng.next_float());
        const float c = rng.next_float();
        const glm::vec2 u{rng.next_float(), rng.next_float()};
        glm::vec3 d;
        if (c < 0.2f) {
            d = sample_uniform_sphere(u);
        } else {
            // cos theta = u^(1/(n+1)), n = 50.
            const float ct = std::pow(u.x, 1.0f / 51.0f);
            const float st = std::sqrt(std::max(0.0f, 1.0f - ct * ct));
            d = Frame::from_normal(axis).to_world(
                {st * std::cos(2.0f * kPi * u.y), st * std::sin(2.0f * kPi * u.y), ct});
        }
        out.push_back({p, d, 1.0f});
    }
    return out;
}

GuidingSettings filtered_settings() {
    GuidingSettings g;
    g.enabled = true;
    g.filter_records = true;
    g.spatial_threshold = 500;
    return g;
}

/// Three passes of `records` (fed in forward or reverse order) into a fresh tree.
void train(SdTree& tree, const std::vector<Record>& records, bool reverse) {
    for (int pass = 0; pass < 3; ++pass) {
        for (std::size_t i = 0; i < records.size(); ++i) {
            const Record& r = records[reverse ? records.size() - 1 - i : i];
            tree.record(tree.leaf_at(r.p), r.p, r.dir, r.flux);
        }
        tree.end_pass(pass);
    }
}

TEST(GuidingFilter, LearnedDensitiesStayNormalisedAndSampled) {
    SdTree tree(BBox{glm::vec3(0.0f), glm::vec3(1.0f)}, filtered_settings());
    train(tree, lobe_records(9, 60000), false);
    ASSERT_GT(tree.leaf_count(), 4u) << "the spatial tree never split";
    // Every leaf's density integrates to 1 over the square (midpoints of a grid finer
    // than its cells: exact for a piecewise-constant density).
    for (std::size_t i = 0; i < tree.leaf_count(); ++i) {
        const QuadTree& q = tree.leaf(i).sampling;
        ASSERT_GT(q.total(), 0.0f) << "leaf " << i << " learned nothing";
        const int depth = q.depth();
        ASSERT_LE(depth, 10) << "leaf " << i;
        const int n = 1 << depth;
        double sum = 0.0;
        for (int y = 0; y < n; ++y)
            for (int x = 0; x < n; ++x)
                sum += q.pdf_square({(float(x) + 0.5f) / float(n), (float(y) + 0.5f) / float(n)});
        EXPECT_NEAR(sum / (double(n) * double(n)), 1.0, 1e-4) << "leaf " << i;
    }
    // Leaf 0's sampler follows its pdf: Pearson's chi-square over 32 x 32 cells of the
    // square, expected counts integrated exactly on a 2^10 grid, 2 x 10^5 samples.
    const QuadTree& q = tree.leaf(0).sampling;
    const int cells = 32, fine = 1 << 10, per = fine / cells;
    const double samples = 2e5;
    std::vector<double> expected(std::size_t(cells * cells), 0.0), observed(expected.size(), 0.0);
    for (int y = 0; y < fine; ++y)
        for (int x = 0; x < fine; ++x)
            expected[std::size_t((y / per) * cells + x / per)] +=
                double(q.pdf_square(
                    {(float(x) + 0.5f) / float(fine), (float(y) + 0.5f) / float(fine)})) *
                samples / (double(fine) * double(fine));
    Pcg32 rng(77, 5);
    for (int i = 0; i < int(samples); ++i) {
        const glm::vec2 p = q.sample_square({rng.next_float(), rng.next_float()});
        observed[std::size_t(int(p.y * cells) * cells + int(p.x * cells))] += 1.0;
    }
    const testing::ChiSquareResult r = testing::chi_square_test(observed, expected);
    EXPECT_TRUE(r.error.empty()) << r.summary();
    EXPECT_GE(r.p_value, 1e-3) << r.summary();
}

// Records all made at one point still teach the leaves around it (the box is a leaf wide):
// several leaves learn something, where unfiltered only the leaf holding the point does.
TEST(GuidingFilter, RecordsReachNeighbouringLeaves) {
    std::size_t learned[2] = {0, 0};
    for (const bool filter : {false, true}) {
        GuidingSettings g = filtered_settings();
        g.filter_records = filter;
        SdTree tree(BBox{glm::vec3(0.0f), glm::vec3(1.0f)}, g);
        // Split the tree with spread records first, then record only at one point.
        std::vector<Record> records = lobe_records(21, 40000);
        train(tree, records, false);
        ASSERT_GT(tree.leaf_count(), 8u);
        const glm::vec3 p(0.5f, 0.5f, 0.5f);
        // Fewer than c sqrt(2^3) = 1414: the leaf holding p does not split.
        for (std::size_t i = 0; i < 1000; ++i)
            tree.record(tree.leaf_at(p), p, records[i].dir, records[i].flux);
        tree.end_pass(3);
        for (std::size_t i = 0; i < tree.leaf_count(); ++i)
            if (tree.leaf(i).sampling.total() > 0.0f) ++learned[filter ? 1 : 0];
    }
    EXPECT_EQ(learned[0], 1u);
    EXPECT_GT(learned[1], 1u);
}

// Fixed-point sums and hashed jitter: records in reverse order teach the same tree, bit
// for bit (a multithreaded pass records in an order that changes from run to run).
TEST(GuidingFilter, OrderOfRecordsChangesNothing) {
    const std::vector<Record> records = lobe_records(33, 30000);
    SdTree forward(BBox{glm::vec3(0.0f), glm::vec3(1.0f)}, filtered_settings());
    SdTree backward(BBox{glm::vec3(0.0f), glm::vec3(1.0f)}, filtered_settings());
    train(forward, records, false);
    train(backward, records, true);
    ASSERT_EQ(forward.leaf_count(), backward.leaf_count());
    for (std::size_t i = 0; i < forward.leaf_count(); ++i) {
        const auto& a = forward.leaf(i).sampling.nodes();
        const auto& b = backward.leaf(i).sampling.nodes();
        ASSERT_EQ(a.size(), b.size()) << "leaf " << i;
        for (std::size_t n = 0; n < a.size(); ++n)
            EXPECT_EQ(std::memcmp(a[n].flux.data(), b[n].flux.data(), sizeof(float) * 4), 0)
                << "leaf " << i << " node " << n;
    }
}

}  // namespace
}  // namespace librt
