#pragma once

#include <cstdint>

// Path guiding (Müller, Gross and Novák 2017, "Practical Path Guiding for Efficient
// Light-Transport Simulation"): PathTracer learns the incident radiance of the scene in
// training passes and then samples directions from it, mixed with BSDF sampling. The
// learned field is an SD-tree (a spatial binary tree whose leaves hold directional
// quadtrees); its code is private (librt/src/integrator/guiding/). docs/sampling.md has the
// figures.

namespace librt {

/// How PathTracer guides its paths. Off by default: then images are bit-identical to an
/// unguided PathTracer's and cost nothing extra.
struct GuidingSettings {
    bool enabled = false;  ///< learn the incident radiance and sample directions from it
    /// Training passes before the image, in [1, 20]; pass k renders 2^k samples per pixel
    /// (1, 2, 4, ...), which are discarded: the default 5 costs 31 samples per pixel. The
    /// distribution learned by the last pass is frozen and guides the image.
    int training_passes = 5;
    /// Probability, in (0, 1], of sampling the BSDF rather than the learned distribution
    /// at a guided vertex (the paper's 0.5; 0.7 measured better on smallpt's scene and the
    /// gap room, docs/sampling.md). Directions are weighted by the mixture's density
    /// (one-sample MIS, balance heuristic), so the image is unbiased whatever was learned;
    /// 1 switches guided sampling off while training still runs.
    float bsdf_fraction = 0.7f;
    /// The paper's c: a spatial leaf is halved while it holds more than
    /// c sqrt(2^k) path vertices recorded in pass k, in [1, 2^30].
    std::uint32_t spatial_threshold = 12000;
    /// A directional cell is refined while it holds more than this fraction of its
    /// leaf's flux, in (0, 1) (the paper's rho = 0.01).
    float flux_threshold = 0.01f;
    /// Deepest level of the directional quadtrees, in [1, 20] (the paper's 20).
    int max_quadtree_depth = 20;
    /// Keep the training passes' samples in the image: every pass from the second on is
    /// combined with the image, each weighted by the inverse of its variance estimated
    /// from two halves of its samples (Müller et al. 2017; Müller 2019), so training time
    /// is not wasted. render() does it itself; render_progressive and render_mpi give the
    /// same image through their `image` argument; with render_block, train() and
    /// PassCombination (renderer.h says how). The apps' --guiding sets it.
    bool keep_training_samples = false;
    /// Splat each record into the spatial leaf at a point jittered uniformly within a box
    /// of the record's leaf's size around it, and into the directional cell at a point
    /// jittered within its cell (stochastic box filtering, Müller et al. 2017, section
    /// 5.3). The jitter hashes the record, so it stays deterministic. Off by default: on
    /// the rooms measured (docs/sampling.md) records leak through walls into leaves that
    /// cannot see what they saw, and the error at equal time rose.
    bool filter_records = false;
};

}  // namespace librt
