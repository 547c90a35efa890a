// The same incoherent rays at the bunny through each layer of a closest-hit query, to tell
// what scene.intersect (Python) pays beyond librt_bench's bare TriangleBvh
// (docs/benchmarks.md, "The Python module against the C++"):
//
//   librt_query_layers bvh|bvh_normal|top|geometric|scene [RAYS] [DATA_DIR]
//       Mrays per CPU s (1 thread, median of 5); bvh_normal: TriangleBvh::intersect with the
//       leaf's winding normal, geometric: Scene::intersect -> GeometricHit (what
//       scene.intersect calls)
//   librt_query_layers dump [RAYS] [DATA_DIR]            writes rays.bin and mesh.bin, which
//       bench/python/intersect_throughput.py --same-rays reads, so Python traces these rays
//
// Under valgrind --tool=callgrind the per-layer instruction counts come from the same run.

#include "../../tests/ray_sets.h"

#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/procedural.h>
#include <librt/material/material.h>
#include <librt/obj/obj.h>
#include <librt/scene/scene.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

namespace {

using namespace librt;

double cpu_seconds() {
    timespec t{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

// The median rate of five passes of `trace` over the rays (trace returns the hit count).
template <class Trace>
void report(const char* layer, const std::vector<Ray>& rays, Trace&& trace) {
    std::vector<double> rates;
    std::size_t hits = 0;
    for (int pass = 0; pass < 5; ++pass) {
        const double start = cpu_seconds();
        hits = trace();
        rates.push_back(double(rays.size()) / (cpu_seconds() - start) * 1e-6);
    }
    std::sort(rates.begin(), rates.end());
    std::printf("%s: %.2f Mrays/CPU s (median of 5), %.1f %% hit\n", layer, rates[2],
                100.0 * double(hits) / double(rays.size()));
}

int usage() {
    std::fprintf(
        stderr,
        "usage: librt_query_layers bvh|bvh_normal|top|geometric|scene|dump [RAYS] [DATA_DIR]\n");
    return 2;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) return usage();
    const std::string layer = argv[1];
    const std::size_t count = argc > 2 ? std::strtoul(argv[2], nullptr, 10) : 1'000'000;
    const std::filesystem::path data = argc > 3 ? argv[3] : LIBRT_DEFAULT_DATA_DIR;
    // Centred and scaled to a diagonal of 100, as bench/bvh_bench.cpp does.
    TriangleMesh mesh = load_obj(data / "stanford-bunny.obj");
    const BBox b = mesh.bounds();
    const float scale = 100.0f / glm::length(b.diagonal());
    transform(mesh, make_transform(glm::vec3(scale), glm::vec3(0.0f), -scale * b.center()));
    const std::vector<Ray> rays = librt::testing::incoherent_rays(mesh.bounds(), count, 42);
    if (layer == "dump") {
        std::FILE* f = std::fopen("rays.bin", "wb");
        for (const Ray& r : rays) {
            const float v[6] = {r.origin.x,    r.origin.y,    r.origin.z,
                                r.direction.x, r.direction.y, r.direction.z};
            std::fwrite(v, sizeof(float), 6, f);
        }
        std::fclose(f);
        f = std::fopen("mesh.bin", "wb");
        const auto nv = std::uint32_t(mesh.positions.size());
        const auto nt = std::uint32_t(mesh.triangles.size());
        std::fwrite(&nv, 4, 1, f);
        std::fwrite(&nt, 4, 1, f);
        std::fwrite(mesh.positions.data(), sizeof(glm::vec3), nv, f);
        std::fwrite(mesh.triangles.data(), sizeof(glm::uvec3), nt, f);
        std::fclose(f);
        std::printf("wrote rays.bin (%zu rays) and mesh.bin (%u triangles)\n", rays.size(), nt);
        return 0;
    }
    if (layer == "bvh") {
        const TriangleBvh bvh(mesh);
        report("TriangleBvh::intersect", rays, [&] {
            std::size_t hits = 0;
            for (const Ray& r : rays) hits += bvh.intersect(r).valid();
            return hits;
        });
        return 0;
    }
    if (layer == "bvh_normal") {
        const TriangleBvh bvh(mesh);
        report("TriangleBvh::intersect + winding normal", rays, [&] {
            std::size_t hits = 0;
            for (const Ray& r : rays) {
                glm::vec3 n;
                hits += bvh.intersect(r, n).valid();
            }
            return hits;
        });
        return 0;
    }
    if (layer != "top" && layer != "scene" && layer != "geometric") return usage();
    Scene scene;
    scene.add_mesh(std::move(mesh), scene.add_material(Material::diffuse(glm::vec3(0.8f))));
    scene.commit();
    if (layer == "top") {
        report("TopLevel::intersect (ObjectHit)", rays, [&] {
            std::size_t hits = 0;
            for (const Ray& r : rays) {
                ObjectHit h;
                hits += scene.top_level().intersect(r, h);
            }
            return hits;
        });
    } else if (layer == "geometric") {
        report("Scene::intersect (GeometricHit)", rays, [&] {
            std::size_t hits = 0;
            for (const Ray& r : rays) {
                GeometricHit h;
                hits += scene.intersect(r, h);
            }
            return hits;
        });
    } else {
        report("Scene::intersect (Hit)", rays, [&] {
            std::size_t hits = 0;
            for (const Ray& r : rays) {
                Hit h;
                hits += scene.intersect(r, h);
            }
            return hits;
        });
    }
    return 0;
}
