#include "bvh_timing.h"

#include <librt/accel/triangle_bvh.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <vector>

namespace librt::apps {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) {
    return std::chrono::duration<double>(Clock::now() - t).count();
}

}  // namespace

void print_bvh_timing(const TriangleMesh& mesh, BvhBuilder builder, const Camera& camera) {
    // Pinhole centre rays of every pixel, in scanline order.
    CameraSettings pinhole = camera.settings();
    pinhole.pixel_jitter = PixelJitter::None;
    pinhole.lens = LensModel::Pinhole;
    const Camera centre(pinhole);
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(centre.width()) *
                 static_cast<std::size_t>(centre.height()));
    for (int y = 0; y < centre.height(); ++y) {
        for (int x = 0; x < centre.width(); ++x) {
            Sampler sampler(0, 0, 0, 0);
            rays.push_back(centre.generate_ray(x, y, sampler));
        }
    }

    const Clock::time_point build_start = Clock::now();
    const TriangleBvh bvh(mesh, builder);
    const double build_seconds = seconds_since(build_start);
    const TriangleList list(mesh);

    std::size_t bvh_hits = 0;
    const Clock::time_point bvh_start = Clock::now();
    for (const Ray& r : rays) bvh_hits += bvh.intersect(r).valid() ? 1u : 0u;
    const double bvh_seconds = std::max(seconds_since(bvh_start), 1e-9);

    // The linear scan is slow: every stride-th ray only, compared with the BVH on the same rays.
    const std::size_t stride = std::max<std::size_t>(1, rays.size() / 2000);
    std::size_t scanned = 0;
    std::size_t mismatches = 0;
    const Clock::time_point list_start = Clock::now();
    for (std::size_t i = 0; i < rays.size(); i += stride, ++scanned) {
        const PrimitiveHit a = list.intersect(rays[i]);
        const PrimitiveHit b = bvh.intersect(rays[i]);
        mismatches += (a.valid() != b.valid() || (a.valid() && a.t != b.t)) ? 1u : 0u;
    }
    const double list_seconds = std::max(seconds_since(list_start), 1e-9);

    const double bvh_rate = static_cast<double>(rays.size()) / bvh_seconds;
    const double list_rate = static_cast<double>(scanned) / list_seconds;
    std::printf("mesh: %zu triangles; %s BVH: %zu nodes built in %.1f ms\n", mesh.triangle_count(),
                builder == BvhBuilder::Median ? "median-split" : "SAH", bvh.stats().node_count,
                build_seconds * 1e3);
    std::printf(
        "primary rays vs the mesh alone: BVH %.2f Mrays/s (%zu hits), linear scan %.4f Mrays/s: "
        "%.0fx faster%s\n",
        bvh_rate * 1e-6, bvh_hits, list_rate * 1e-6, bvh_rate / list_rate,
        mismatches == 0 ? "" : " (MISMATCHED HITS)");
}

}  // namespace librt::apps
