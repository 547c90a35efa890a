#pragma once

// An integrator that cancels its own render after a given number of samples, so that the
// cancellation tests stop at a point counted in samples rather than after a sleep (which,
// on a loaded machine, may come before the first sample or after the last one).

#include <librt/integrator/integrator.h>

#include <atomic>
#include <cstdint>

namespace librt::testing {

/// Forwards each sample to `inner` (or returns 1 without one) and, from its `after`-th
/// call on, sets `cancel`: every such call sets it again, on its own thread, so each
/// thread that took one sees the flag at its next check whatever the other threads do.
/// A render that checks the flag every `period` samples of a thread therefore takes at
/// most max_samples(threads, period) samples, and at least `after` before it can stop.
class CancellingIntegrator final : public Integrator {
public:
    CancellingIntegrator(std::atomic<bool>& cancel, std::uint64_t after,
                         Integrator* inner = nullptr)
        : cancel_(cancel), after_(after), inner_(inner) {}

    void preprocess(const Scene& scene) override {
        if (inner_ != nullptr) inner_->preprocess(scene);
    }
    [[nodiscard]] glm::vec3 li(const Scene& scene, const Ray& ray,
                               Sampler& sampler) const override {
        const std::uint64_t call = calls_.fetch_add(1) + 1;
        const glm::vec3 l = inner_ != nullptr ? inner_->li(scene, ray, sampler) : glm::vec3(1.0f);
        if (call >= after_) cancel_.store(true);
        return l;
    }

    /// Samples taken so far (li calls).
    [[nodiscard]] std::uint64_t calls() const { return calls_.load(); }
    /// The `after` - 1 calls before the flag, then at most `period` per thread: the call
    /// that set it and those before the thread's next check.
    [[nodiscard]] std::uint64_t max_samples(unsigned threads, std::uint64_t period) const {
        return after_ - 1 + threads * period;
    }

private:
    std::atomic<bool>& cancel_;
    std::uint64_t after_;
    Integrator* inner_;
    mutable std::atomic<std::uint64_t> calls_{0};
};

}  // namespace librt::testing
