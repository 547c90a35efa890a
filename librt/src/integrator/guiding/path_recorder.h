#pragma once

// The records one training path leaves in the SD-tree: at each guided vertex the
// direction sampled there, the density it was sampled with, and the radiance that arrived
// along it from the rest of the path. That radiance is what the path adds after the vertex
// divided by the throughput up to and including the vertex's own scattering weight,
// per channel; it includes next-event estimates and MIS-weighted emission further on, so
// its expectation is the incident radiance (what the light strategies at that vertex do
// not find is in it; what they find is learned where it is weighted).

#include "integrator/guiding/sd_tree.h"

#include <glm/vec3.hpp>

#include <array>
#include <cstddef>

namespace librt::guiding {

/// The vertices of one path, recorded into the tree when it ends (commit).
class PathRecorder {
public:
    /// Most vertices recorded per path: deeper ones (rare with roulette) are not learned.
    static constexpr std::size_t kMaxVertices = 32;

    /// A vertex at p whose direction `dir` was sampled with density `pdf`, after which the
    /// path's throughput is `beta` (before any roulette reweighting at that vertex).
    void push(const DirLeaf& leaf, const glm::vec3& p, const glm::vec3& dir, float pdf,
              const glm::vec3& beta) {
        if (count_ == kMaxVertices) return;
        // 1 / beta per channel once here: add() then multiplies (a path adds several
        // contributions to each of its vertices, and divisions are slow).
        glm::vec3 inv(0.0f);
        for (int c = 0; c < 3; ++c)
            if (beta[c] > 0.0f) inv[c] = 1.0f / beta[c];
        vertices_[count_++] = Vertex{&leaf, p, dir, pdf, inv, glm::vec3(0.0f)};
    }

    /// Radiance `contribution` (already times the path throughput) reached the camera:
    /// each recorded vertex receives its share of it.
    void add(const glm::vec3& contribution) {
        for (std::size_t i = 0; i < count_; ++i)
            vertices_[i].radiance += contribution * vertices_[i].inv_beta;
    }

    /// Radiance `extra` (times the path throughput) that only the last recorded vertex
    /// receives: the part of an emitter's radiance that MIS gave to the light strategy.
    /// The last vertex's direction did find all of it, and learning the full incident
    /// radiance keeps guiding toward lights that next-event estimation finds badly (one
    /// seen through a gap); earlier vertices keep the MIS-weighted share, which with the
    /// light samples is an unbiased estimate of what reaches them.
    void add_to_last(const glm::vec3& extra) {
        if (count_ == 0) return;
        Vertex& v = vertices_[count_ - 1];
        v.radiance += extra * v.inv_beta;
    }

    /// Records every vertex: flux estimate = mean incident radiance / sampling density.
    void commit(const SdTree& tree) const {
        for (std::size_t i = 0; i < count_; ++i) {
            const Vertex& v = vertices_[i];
            const float l = (v.radiance.x + v.radiance.y + v.radiance.z) * (1.0f / 3.0f);
            tree.record(*v.leaf, v.p, v.dir, l / v.pdf);
        }
    }

private:
    struct Vertex {
        const DirLeaf* leaf;
        glm::vec3 p;
        glm::vec3 dir;
        float pdf;
        glm::vec3 inv_beta;  // 1 / throughput per channel (0 where the throughput is 0)
        glm::vec3 radiance;
    };
    // Not value-initialised: only the first count_ entries are ever read, and zeroing
    // 32 of them per training path showed in profiles.
    std::array<Vertex, kMaxVertices> vertices_;
    std::size_t count_ = 0;
};

}  // namespace librt::guiding
