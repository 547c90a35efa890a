#pragma once

// Combining independent renders of the same image (the training passes of path guiding
// and the image itself) into one estimate, each weighted by the inverse of its variance
// (Müller, Gross and Novák 2017; Müller 2019, "Practical Path Guiding in Production").
// Weights are one number per render, so each pixel stays a weighted mean of unbiased
// estimates; the variance of a render is estimated from two halves of its samples, whose
// difference has no signal in it. train() fills one with the passes an integrator keeps
// (Integrator::keeps_training_samples); combined() joins the image to them, the same way
// in every render entry point, so they all give render()'s image bit for bit.

#include <librt/core/image.h>
#include <librt/export.h>
#include <librt/film/film.h>

#include <glm/ext/vector_double3.hpp>

#include <vector>

namespace librt {

/// The running inverse-variance weighted mean of whole-image renders.
class LIBRT_API PassCombination {
public:
    /// Adds the render `full`, whose first half of samples per pixel is `half` (the film as
    /// it was after them). A render with fewer than 2 samples in a pixel, or whose
    /// estimated variance is 0 or not finite, is skipped (returns false). The variance is
    /// summed over pixels in index order: the same films give the same bits. A render with
    /// splats counts them as resolve() does (pixel mean plus splat sums over the samples
    /// per pixel), each half with its own sums; `half` must then have splats too.
    bool add(const Film& half, const Film& full);

    /// Renders added so far.
    [[nodiscard]] int count() const { return count_; }

    /// The weighted mean (requires count() > 0).
    [[nodiscard]] Image image(int width, int height) const;

    /// The image of the render `full` (its first half of samples per pixel `half`) joined
    /// to the renders added so far, all weighted by inverse variance: render()'s image
    /// with kept training passes. resolve(full) when nothing was added or `full`'s variance
    /// cannot be estimated (fewer than 2 samples, a black image). Leaves this unchanged.
    [[nodiscard]] Image combined(const Film& half, const Film& full) const;

private:
    std::vector<glm::dvec3> sum_;  // sum over renders of weight x pixel mean
    double weight_ = 0.0;          // sum of the weights
    int count_ = 0;
};

}  // namespace librt
