// BVH microbenchmarks: closest-hit and any-hit rays/s for the naive scan, the report's
// median-split BVH and the binned-SAH BVH, on procedural teapots and the shared scans;
// build time and memory per builder. Run: ./build/release/bench/librt_bench
//
// Meshes are centred and scaled to a bounding-box diagonal of 100, as in the reference
// figures of ../shared/data/README.md.

#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/procedural.h>
#include <librt/io/obj.h>

#include <benchmark/benchmark.h>

#include "../tests/ray_sets.h"

#include <glm/geometric.hpp>

#include <cstdlib>
#include <filesystem>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <vector>

namespace {

using namespace librt;
namespace fs = std::filesystem;

constexpr std::size_t kIncoherentRays = 1u << 20;  // per iteration for BVH engines
constexpr std::size_t kNaiveRays = 256;            // the naive scan gets a small subset
constexpr int kPrimaryResolution = 1024;

fs::path data_dir() {
    if (const char* env = std::getenv("LIBRT_DATA_DIR"); env && *env) return env;
    return LIBRT_DEFAULT_DATA_DIR;
}

void normalise(TriangleMesh& mesh) {
    const BBox b = mesh.bounds();
    const float scale = 100.0f / glm::length(b.diagonal());
    transform(mesh, make_transform(glm::vec3(scale), glm::vec3(0.0f), -scale * b.center()));
}

/// A named mesh with its ray sets, built once and shared by every benchmark.
struct Workload {
    std::string name;
    TriangleMesh mesh;
    std::vector<Ray> incoherent;
    std::vector<Ray> primary;
};

std::vector<std::shared_ptr<Workload>> make_workloads() {
    std::vector<std::shared_ptr<Workload>> out;
    auto add = [&](std::string name, TriangleMesh mesh) {
        auto w = std::make_shared<Workload>();
        w->name = std::move(name);
        w->mesh = std::move(mesh);
        normalise(w->mesh);
        const BBox box = w->mesh.bounds();
        w->incoherent = librt::testing::incoherent_rays(box, kIncoherentRays, 42);
        w->primary = librt::testing::primary_rays(box, kPrimaryResolution, kPrimaryResolution, 40.0f);
        out.push_back(std::move(w));
    };
    for (const std::size_t target : {1'000u, 10'000u, 100'000u, 1'000'000u})
        add("teapot" + std::to_string(target / 1000) + "k", make_teapot_with_triangles(target));
    for (const char* file : {"stanford-bunny.obj", "stanford-dragon.obj"}) {
        const fs::path path = data_dir() / file;
        if (!fs::is_regular_file(path)) {
            std::cerr << "librt_bench: " << path << " not found, its rows are skipped "
                      << "(set LIBRT_DATA_DIR)\n";
            continue;
        }
        add(fs::path(file).stem().string().substr(9), load_obj(path));  // "bunny", "dragon"
    }
    return out;
}

template <class Engine>
void trace(benchmark::State& state, const Engine& engine, const std::vector<Ray>& rays,
           std::size_t count, bool any_hit) {
    std::size_t hits = 0;
    for (auto _ : state) {
        for (std::size_t i = 0; i < count; ++i) {
            const bool hit = any_hit ? engine.occluded(rays[i]) : engine.intersect(rays[i]).valid();
            hits += hit;
        }
        benchmark::DoNotOptimize(hits);
    }
    state.counters["Mrays"] = benchmark::Counter(static_cast<double>(count) * 1e-6,
                                                   benchmark::Counter::kIsIterationInvariantRate);
    state.counters["hit%"] = 100.0 * static_cast<double>(hits) /
                             static_cast<double>(count * static_cast<std::size_t>(state.iterations()));
}

void register_all(const std::vector<std::shared_ptr<Workload>>& workloads) {
    for (const auto& w : workloads) {
        const double tris = static_cast<double>(w->mesh.triangle_count());
        for (const auto& [builder_name, builder] :
             {std::pair{"median", BvhBuilder::Median}, std::pair{"sah", BvhBuilder::Sah}}) {
            auto accel = std::make_shared<TriangleBvh>(w->mesh, builder);
            const std::string prefix = w->name + "/bvh_" + builder_name;
            benchmark::RegisterBenchmark((prefix + "/build").c_str(), [w, builder, tris](benchmark::State& s) {
                std::size_t bytes = 0;
                for (auto _ : s) {
                    TriangleBvh b(w->mesh, builder);
                    bytes = b.bvh().memory_bytes();
                    benchmark::DoNotOptimize(bytes);
                }
                s.counters["Mtris"] = benchmark::Counter(tris * 1e-6, benchmark::Counter::kIsIterationInvariantRate);
                s.counters["bvh_bytes/tri"] = static_cast<double>(bytes) / tris;
            })->Unit(benchmark::kMillisecond)->UseRealTime();
            benchmark::RegisterBenchmark((prefix + "/incoherent").c_str(), [w, accel](benchmark::State& s) {
                trace(s, *accel, w->incoherent, w->incoherent.size(), false);
            })->Unit(benchmark::kMillisecond)->UseRealTime();
            benchmark::RegisterBenchmark((prefix + "/incoherent_anyhit").c_str(), [w, accel](benchmark::State& s) {
                trace(s, *accel, w->incoherent, w->incoherent.size(), true);
            })->Unit(benchmark::kMillisecond)->UseRealTime();
            benchmark::RegisterBenchmark((prefix + "/primary").c_str(), [w, accel](benchmark::State& s) {
                trace(s, *accel, w->primary, w->primary.size(), false);
            })->Unit(benchmark::kMillisecond)->UseRealTime();
        }
        if (w->mesh.triangle_count() <= 100'000) {
            auto naive = std::make_shared<TriangleList>(w->mesh);
            benchmark::RegisterBenchmark((w->name + "/naive/incoherent").c_str(), [w, naive](benchmark::State& s) {
                trace(s, *naive, w->incoherent, kNaiveRays, false);
            })->Unit(benchmark::kMillisecond)->UseRealTime();
        }
    }
}

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    register_all(make_workloads());
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    return 0;
}
