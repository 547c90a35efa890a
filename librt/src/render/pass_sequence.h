#pragma once

// The one pass sequence under every render driver (render(), render_progressive() and
// render_mpi's tile jobs): after preprocess() and train(),
//   1. the uniform stage: every pixel to the same count (all its samples, or adaptive
//      sampling's pilot), in two halves when the film at its half is wanted (kept training
//      passes join the image by its halves, PassCombination; the pilot's noise is the
//      difference of its halves' means);
//   2. the counts: each pixel's own count from the pilot (adaptive_sample_counts);
//   3. the rest: every pixel on to its count, in sample order.
// What differs between the drivers is only how a pass is executed (PassRunner): by threads
// over the tiles of the whole image, onto a copy of the film that replaces it once
// complete, or over one tile of an MPI job. Header-only: librt::mpi uses it too.

#include <librt/film/film.h>
#include <librt/integrator/integrator.h>
#include <librt/render/adaptive_sampling.h>
#include <librt/render/renderer.h>

#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <span>
#include <utility>
#include <vector>

namespace librt {

/// What a render of some settings renders: the levels its passes stop at.
struct RenderPlan {
    std::uint32_t spp = 0;    ///< samples per pixel (adaptive sampling: the pixels' mean)
    std::uint32_t pilot = 0;  ///< adaptive sampling's pilot samples per pixel; 0: none
    bool keep = false;        ///< kept training passes join the image (PassCombination)
    AdaptiveSampling adaptive;

    /// Samples every pixel gets before the counts: the pilot, or all of them.
    [[nodiscard]] std::uint32_t uniform_end() const { return pilot > 0 ? pilot : spp; }
    /// Whether the uniform stage is rendered in two halves with the film kept between them.
    [[nodiscard]] bool in_halves() const { return keep || pilot > 0; }
    /// Where the first half ends.
    [[nodiscard]] std::uint32_t half_level() const { return uniform_end() / 2; }

    /// Step 2, the counts: each pixel's own count from its neighbours' pilots (`half`: the
    /// film at half_level(), `pilot_film`: at the pilot).
    [[nodiscard]] std::vector<std::uint32_t> counts(const Film& half,
                                                    const Film& pilot_film) const {
        return adaptive_sample_counts(half, pilot_film, spp, adaptive);
    }
};

/// The plan of validated `settings` as far as it is known before the integrator is asked:
/// the samples and the pilot (adaptive_pilot_samples), keep still false.
inline RenderPlan plan_of(const RenderSettings& settings) {
    RenderPlan plan;
    plan.spp = static_cast<std::uint32_t>(settings.samples_per_pixel);
    plan.adaptive = settings.adaptive;
    plan.pilot =
        settings.adaptive.enabled ? adaptive_pilot_samples(settings.adaptive, plan.spp) : 0;
    return plan;
}

/// Whether the image keeps the integrator's training passes (path guiding's
/// keep_training_samples; asked after preprocess(), which may decide it): only when the
/// image has the 2 samples per pixel its own variance estimate needs, and not with
/// adaptive sampling, whose pixels hold different counts (the combination assumes equal).
inline bool keeps_training_passes(const RenderPlan& plan, const Integrator& integrator) {
    return plan.pilot == 0 && integrator.keeps_training_samples() && plan.spp >= 2;
}

/// How a pass is executed: the seam between the sequence and a driver.
struct PassRunner {
    /// Renders samples [first, first + count) of every pixel; with `ends` (the rest stage:
    /// one per film pixel) each pixel from `first` on to its own end instead. Returns
    /// false when the pass stopped before its end (cancelled): the sequence stops.
    std::function<bool(std::uint32_t first, std::uint32_t count, const std::uint32_t* ends)> pass;
    /// Every pixel holds half_level() samples (in_halves() only): keep the film as it is.
    std::function<void()> reached_half;
    /// After each complete pass (and the counts, when it completed the pilot): the level
    /// the passes reached. Optional.
    std::function<void(std::uint32_t level)> passed;
};

/// Runs a plan's passes from `level` (samples every pixel holds), each at most `max_pass`
/// samples per pixel, through a PassRunner.
class PassSequence {
public:
    static constexpr std::uint32_t kWholeStages = std::numeric_limits<std::uint32_t>::max();

    PassSequence(const RenderPlan& plan, std::uint32_t level, std::uint32_t max_pass = kWholeStages)
        : plan_(plan), level_(level), max_pass_(max_pass) {}

    /// All three steps, to plan.spp; the counts come from the films `half` and `film`
    /// (the runner's) once the pilot is complete. False when a pass stopped early.
    bool run(const PassRunner& runner, const Film& half, const Film& film) {
        half_ = &half;
        film_ = &film;
        return advance(runner, plan_.spp);
    }

    /// Step 1 alone: to plan.uniform_end().
    bool run_uniform(const PassRunner& runner) { return advance(runner, plan_.uniform_end()); }

    /// Step 3 alone, from the pilot to `counts` (one per film pixel), computed elsewhere
    /// (render_mpi's rank 0 computes them from the whole image's pilot).
    bool run_rest(const PassRunner& runner, std::span<const std::uint32_t> counts) {
        rest_counts_ = counts;
        return advance(runner, plan_.spp);
    }

    /// Samples every pixel holds (in the rest stage: the level the passes reached).
    [[nodiscard]] std::uint32_t level() const { return level_; }
    /// Each pixel's count once the pilot is complete (run() only; else empty).
    [[nodiscard]] const std::vector<std::uint32_t>& counts() const { return counts_; }

private:
    bool advance(const PassRunner& runner, std::uint32_t end) {
        // A film resumed exactly at the half is its own half.
        if (plan_.in_halves() && level_ == plan_.half_level() && level_ < end)
            runner.reached_half();
        while (level_ < end) {
            std::uint32_t count = std::min(max_pass_, end - level_);
            const std::uint32_t* ends = nullptr;
            if (plan_.in_halves() && level_ < plan_.half_level()) {
                count = std::min(count, plan_.half_level() - level_);
            } else if (level_ < plan_.uniform_end()) {
                count = std::min(count, plan_.uniform_end() - level_);
            } else {
                ends = rest_ends(level_ + count);
            }
            if (!runner.pass(level_, count, ends)) return false;
            level_ += count;
            if (plan_.in_halves() && level_ == plan_.half_level()) runner.reached_half();
            if (plan_.pilot > 0 && level_ == plan_.pilot && rest_counts_.empty() &&
                film_ != nullptr) {
                counts_ = plan_.counts(*half_, *film_);
                rest_counts_ = counts_;
            }
            if (runner.passed) runner.passed(level_);
        }
        return true;
    }

    // Each pixel's end for a rest pass ending at `level`: the same fraction of the way from
    // the pilot to its count, pilot + floor((N_p - pilot) (level - pilot) / (spp - pilot)),
    // so a film stopped between passes holds each pixel's share (N_p at level spp).
    const std::uint32_t* rest_ends(std::uint32_t level) {
        if (level == plan_.spp) return rest_counts_.data();
        const std::uint64_t step = level - plan_.pilot;
        const std::uint64_t span = plan_.spp - plan_.pilot;
        goals_.resize(rest_counts_.size());
        for (std::size_t i = 0; i < rest_counts_.size(); ++i)
            goals_[i] = plan_.pilot + std::uint32_t((rest_counts_[i] - plan_.pilot) * step / span);
        return goals_.data();
    }

    RenderPlan plan_;
    std::uint32_t level_;
    std::uint32_t max_pass_;
    const Film* half_ = nullptr;
    const Film* film_ = nullptr;
    std::vector<std::uint32_t> counts_;           // run(): computed from the pilot
    std::span<const std::uint32_t> rest_counts_;  // the counts the rest stage renders to
    std::vector<std::uint32_t> goals_;            // the ends of a rest pass short of spp
};

}  // namespace librt
