// PathTracer's guiding members besides li() (which needs the path loop, integrators.cpp):
// the SD-tree's life cycle over preprocess() and the training passes.

#include "integrator/guiding/sd_tree.h"

#include <librt/integrator/integrators.h>
#include <librt/scene/scene.h>

namespace librt {

PathTracer::~PathTracer() = default;

void PathTracer::preprocess(const Scene& scene) {
    sphere_ = scene.bounding_sphere();
    guide_.reset();
    recording_ = false;
    if (settings_.guiding.enabled)
        guide_ = std::make_unique<guiding::SdTree>(scene.bounds(), settings_.guiding);
}

std::uint32_t PathTracer::begin_training_pass(int pass) {
    recording_ = false;
    if (guide_ == nullptr || pass < 0 || pass >= settings_.guiding.training_passes) return 0;
    recording_ = true;
    return std::uint32_t{1} << static_cast<std::uint32_t>(pass);
}

void PathTracer::end_training_pass(int pass) {
    if (guide_ == nullptr || !recording_) return;
    guide_->end_pass(pass);
    recording_ = false;
}

bool PathTracer::keeps_training_samples() const {
    return guide_ != nullptr && settings_.guiding.keep_training_samples;
}

std::size_t PathTracer::guiding_leaf_count() const {
    return guide_ != nullptr ? guide_->leaf_count() : 0;
}

}  // namespace librt
