#pragma once

// Combining independent renders of the same image (the training passes of path guiding
// and the image itself) into one estimate, each weighted by the inverse of its variance
// (Müller, Gross and Novák 2017; Müller 2019, "Practical Path Guiding in Production").
// Weights are one number per render, so each pixel stays a weighted mean of unbiased
// estimates; the variance of a render is estimated from two halves of its samples, whose
// difference has no signal in it.

#include <librt/core/image.h>
#include <librt/render/film.h>

#include <glm/ext/vector_double3.hpp>

#include <vector>

namespace librt {

/// The running inverse-variance weighted mean of whole-image renders.
class PassCombination {
public:
    /// Adds the render `full`, whose first half of samples per pixel is `half` (the film as
    /// it was after them). A render with fewer than 2 samples in a pixel, or whose
    /// estimated variance is 0 or not finite, is skipped (returns false).
    bool add(const Film& half, const Film& full);

    /// Renders added so far.
    [[nodiscard]] int count() const { return count_; }

    /// The weighted mean (requires count() > 0).
    [[nodiscard]] Image image(int width, int height) const;

private:
    std::vector<glm::dvec3> sum_;  // sum over renders of weight x pixel mean
    double weight_ = 0.0;          // sum of the weights
    int count_ = 0;
};

}  // namespace librt
