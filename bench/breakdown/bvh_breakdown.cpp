// Where a librt_bench row's time goes, by counts rather than by time (issue 40, item 1): the
// same mesh and rays as librt_bench's <mesh>/librt_vs_embree/<rays>/1t row, then
//   - the shape of librt's tree (TriangleBvh::stats(), with the surface-area figures Embree
//     prints for its own tree under LIBRT_EMBREE_CONFIG=verbose=2) and bytes per triangle of
//     both engines;
//   - per ray, the nodes, leaves, blocks and triangles librt's traversal tests
//     (TriangleBvh::count_traversal);
//   - the rays traced through librt and through Embree in two functions of their own,
//     trace_librt and trace_embree, for callgrind to count instructions and cache misses of
//     each engine on the same rays:
//       valgrind --tool=callgrind --cache-sim=yes --collect-atstart=no
//           --toggle-collect='*trace_librt*' --toggle-collect='*trace_embree*'
//           build/release/bench/librt_bvh_breakdown dragon anyhit
//     (valgrind has no AVX-512: under it librt and Embree both run their AVX2 code). Each
//     trace starts after 64 MiB of other data went through the caches; add
//     --LL=33554432,16,64 for this machine's 32 MiB L3 (valgrind reads a bigger one here).
//
// Run: librt_bvh_breakdown <bunny|dragon|teapot1m> <incoherent|anyhit|primary> [rays]
// (rays: how many of the row's rays, spread evenly over the set; default 65536).

#include "../../tests/ray_sets.h"
#include "../embree_scene.h"

#include <librt/accel/bvh_stats.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/procedural.h>
#include <librt/obj/obj.h>

#include <glm/geometric.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace librt;

/// librt_bench's normalisation: centred, bounding-box diagonal 100.
void normalise(TriangleMesh& mesh) {
    const BBox b = mesh.bounds();
    const float scale = 100.0f / glm::length(b.diagonal());
    transform(mesh, make_transform(glm::vec3(scale), glm::vec3(0.0f), -scale * b.center()));
}

TriangleMesh load_mesh(const std::string& name) {
    if (name == "teapot1m") return make_teapot_with_triangles(1'000'000);
    const char* env = std::getenv("LIBRT_DATA_DIR");
    const std::filesystem::path dir = env && *env ? env : LIBRT_DEFAULT_DATA_DIR;
    return load_obj(dir / ("stanford-" + name + ".obj"));
}

/// `count` of the set's rays, evenly spaced (all of them when count is larger).
std::vector<Ray> pick(const std::vector<Ray>& all, std::size_t count) {
    if (count >= all.size()) return all;
    std::vector<Ray> out(count);
    for (std::size_t i = 0; i < count; ++i) out[i] = all[i * all.size() / count];
    return out;
}

template <class Engine>
std::size_t trace(const Engine& engine, const std::vector<Ray>& rays, bool any_hit) {
    std::size_t hits = 0;
    for (const Ray& r : rays) hits += any_hit ? engine.occluded(r) : engine.intersect(r).valid();
    return hits;
}

// Out of line and named, so callgrind can collect each engine alone.
[[gnu::noinline]] std::size_t trace_librt(const TriangleBvh& bvh, const std::vector<Ray>& rays,
                                          bool any_hit) {
    return trace(bvh, rays, any_hit);
}
[[gnu::noinline]] std::size_t trace_embree(const bench::EmbreeScene& scene,
                                           const std::vector<Ray>& rays, bool any_hit) {
    return trace(scene, rays, any_hit);
}

/// Writes and reads 64 MiB, so that neither engine starts its trace with the other's (or its
/// own build's, or the counting pass's) data in a 32 MiB last-level cache.
[[gnu::noinline]] void evict_caches() {
    static std::vector<unsigned char> junk(std::size_t{64} << 20);
    unsigned sum = 0;
    for (std::size_t i = 0; i < junk.size(); i += 64) sum += junk[i]++;
    if (sum == 1) std::puts("");  // keep the loop
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 3) {
        std::fprintf(stderr,
                     "usage: librt_bvh_breakdown <bunny|dragon|teapot1m> "
                     "<incoherent|anyhit|primary> [rays]\n");
        return 2;
    }
    const std::string mesh_name = argv[1], kind = argv[2];
    if (kind != "incoherent" && kind != "anyhit" && kind != "primary") {
        std::fprintf(stderr, "librt_bvh_breakdown: unknown ray set '%s'\n", kind.c_str());
        return 2;
    }
    const std::size_t count = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 65536;
    const bool any_hit = kind == "anyhit";

    TriangleMesh mesh = load_mesh(mesh_name);
    normalise(mesh);
    const BBox box = mesh.bounds();
    const std::vector<Ray> rays =
        pick(kind == "primary" ? testing::primary_rays(box, 1024, 1024, 40.0f)
                               : testing::incoherent_rays(box, 1u << 20, 42),
             count);
    const double tris = static_cast<double>(mesh.triangle_count());

    const TriangleBvh bvh(mesh);
    const BvhStats s = bvh.stats();
    std::printf("%s, %zu triangles, %s, %zu rays\n", mesh_name.c_str(), mesh.triangle_count(),
                kind.c_str(), rays.size());
    std::printf(
        "librt tree: %zu nodes, %zu leaves, depth %u, %.1f B/tri, "
        "sah nodes %.3f leaves %.3f (leaf blocks)\n",
        s.node_count, s.leaf_count, s.depth, double(s.bytes) / tris, s.node_sah, s.leaf_sah);

    TraversalCounts c;
    for (const Ray& r : rays) c += bvh.count_traversal(r, any_hit);
    const double n = static_cast<double>(rays.size());
    std::printf(
        "librt per ray: %.2f nodes, %.2f leaves, %.2f blocks, %.2f triangles, "
        "%.2f pushes, %.2f culled pops\n",
        double(c.nodes) / n, double(c.leaves) / n, double(c.blocks) / n, double(c.triangles) / n,
        double(c.pushes) / n, double(c.culled) / n);

    evict_caches();
    const std::size_t hits_librt = trace_librt(bvh, rays, any_hit);
    std::printf("librt hits: %zu\n", hits_librt);
    if (bench::embree_available()) {
        const bench::EmbreeScene scene(mesh);
        std::printf("embree: %.1f B/tri\n", double(scene.memory_bytes()) / tris);
        evict_caches();
        std::printf("embree hits: %zu\n", trace_embree(scene, rays, any_hit));
    }
    return 0;
}
