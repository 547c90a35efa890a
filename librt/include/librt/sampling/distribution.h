#pragma once

#include <librt/export.h>

#include <glm/vec2.hpp>

#include <cstddef>
#include <span>
#include <vector>

namespace librt {

/// A piecewise-constant density on [0, 1) from n non-negative weights (pbrt 4th ed. A.4.1):
/// cell i has probability w_i / sum(w) and is sampled by inverting the CDF. All-zero (or
/// empty) weights give the uniform density.
class LIBRT_API Distribution1D {
public:
    /// The uniform density over one cell.
    Distribution1D() : Distribution1D(std::span<const float>{}) {}
    /// The density proportional to `weights` (negative or non-finite ones read as 0).
    explicit Distribution1D(std::span<const float> weights);

    /// A point x in [0, 1) drawn by u in [0, 1), its density and cell.
    struct Sample {
        float x = 0.0f;        ///< in [0, 1)
        float pdf = 0.0f;      ///< density at x, per unit length
        std::size_t cell = 0;  ///< index of the cell holding x
    };
    /// Inverts the CDF at u.
    [[nodiscard]] Sample sample(float u) const;
    /// Density at cell i (per unit length of [0, 1)).
    [[nodiscard]] float pdf(std::size_t i) const { return pdf_[i]; }
    /// Number of cells.
    [[nodiscard]] std::size_t size() const { return pdf_.size(); }
    /// Sum of the weights over n: the mean of the function.
    [[nodiscard]] double integral() const { return integral_; }

private:
    std::vector<float> pdf_;  ///< per cell, mean 1
    std::vector<float> cdf_;  ///< size n + 1, cdf_[0] = 0, cdf_[n] = 1
    double integral_ = 0.0;
};

/// A piecewise-constant density on [0, 1)^2 over a width x height grid (row-major, row y
/// at v in [y / height, (y + 1) / height)): a marginal over rows, then a conditional over
/// the columns of the chosen row (pbrt 4th ed. A.5.6).
class LIBRT_API Distribution2D {
public:
    /// The uniform density on one cell.
    Distribution2D() : Distribution2D({}, 1, 1) {}
    /// The density proportional to `weights` (width * height of them; the empty span
    /// gives the uniform density).
    Distribution2D(std::span<const float> weights, int width, int height);

    /// A point (u, v) drawn by u2, with its density per unit area of [0, 1)^2.
    struct Sample {
        glm::vec2 uv{0.0f};  ///< the point
        float pdf = 0.0f;    ///< density at it
    };
    /// Draws (u, v) from the density.
    [[nodiscard]] Sample sample(glm::vec2 u) const;
    /// Density at (u, v) in [0, 1)^2 (clamped to the grid).
    [[nodiscard]] float pdf(glm::vec2 uv) const;

private:
    int width_ = 1;
    int height_ = 1;
    std::vector<Distribution1D> rows_;  ///< conditional over columns, per row
    Distribution1D marginal_;           ///< over rows
};

}  // namespace librt
