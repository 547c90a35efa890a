// BVH microbenchmarks: librt against Embree 3 on the same meshes and rays, in one run.
//
// Engines: "naive" (TriangleList, small meshes and few rays only), "median" and "sah"
// (the binary BVHs through the generic traverse<>), "librt" (TriangleBvh, the fast path
// the renderer uses) and "embree" (rtcIntersect1 / rtcOccluded1, when CMake found it).
//
// librt and Embree are measured in the same rows, named <mesh>/librt_vs_embree/<rays>/<threads>
// and <mesh>/librt_vs_embree/build: the rays go in chunks of 32768, each chunk through both
// engines (alternating which goes first), so both see the same machine load, which on a
// shared machine drifts faster than a benchmark row lasts. Counters: librt_Mrays,
// embree_Mrays and their ratio (librt / Embree; for builds librt_ms, embree_ms, their ratio,
// and bytes per triangle). Rows <mesh>/librt_vs_embree_hq/... are the same with Embree at
// RTC_BUILD_QUALITY_HIGH (spatial splits) instead of its default quality; their embree_*
// counters are the high-quality tree's; rows <mesh>/librt_vs_embree_robust/<rays>/1t have
// Embree with RTC_SCENE_FLAG_ROBUST (its Pluecker test on the vertices, as watertight as
// librt's test; default build quality). Without Embree the rows are <mesh>/librt/... with
// librt's counters only. The binary BVHs and the naive scan have rows of their own
// (<mesh>/<engine>/incoherent/1t, counter Mrays; <mesh>/<engine>/build).
//
// Rays: "incoherent" (closest hit), "anyhit" (the same rays through occluded()) and
// "primary" (1024x1024 pinhole), see tests/ray_sets.h; "miss" (closest hit, 1t) are the
// incoherent rays' directions from origins outside the mesh's box, pointing away from it:
// every ray leaves at the root node, so the row times the per-ray setup and one node test.
// Every mesh has the incoherent and any-hit 1t rows (the small teapots' trees stay in the
// caches); the headline meshes (teapot 1M, bunny, dragon) have all of them. "1t" rows trace
// on the calling thread and count rays / thread CPU time; "<N>t" rows split the chunks over N
// std::threads (N = hardware threads) and count rays / (summed thread CPU time / N): the rate
// of N dedicated cores. Builds count wall time (both builders use all cores).
//
// Rows <mesh>/librt_stream_vs_embree/<incoherent|anyhit|primary>/1t time TriangleBvh's ray
// streams (intersect(rays, hits), occluded(rays, blocked)) beside Embree's stream API
// (rtcIntersect1M / rtcOccluded1M) and both engines' single rays, four engines on the same
// chunks (see trace_stream_row).
//
// After the run a summary table prints librt beside Embree with the ratio (medians when
// --benchmark_repetitions is given).
//
// Run: ./build/release/bench/librt_bench [--benchmark_filter=bunny] [--benchmark_repetitions=3]
// Meshes are centred and scaled to a bounding-box diagonal of 100, as in the reference
// figures of ../shared/data/README.md.
//
// One file of ~580 lines, over the usual 400: the workloads, the paired timing and the
// summary table share the Workload records and the row-name scheme above, and splitting them
// would only move those shared declarations into a header of their own.

#include "../tests/ray_sets.h"
#include "embree_scene.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/procedural.h>
#include <librt/obj/obj.h>

#include <benchmark/benchmark.h>

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <type_traits>
#include <vector>

namespace {

using namespace librt;
namespace fs = std::filesystem;

constexpr std::size_t kIncoherentRays = 1u << 20;  // per iteration for fast engines
constexpr std::size_t kBinaryRays = 1u << 18;      // the binary BVHs trace a prefix
constexpr std::size_t kNaiveRays = 256;            // the naive scan gets a small subset
constexpr int kPrimaryResolution = 1024;

fs::path data_dir() {
    if (const char* env = std::getenv("LIBRT_DATA_DIR"); env && *env) return env;
    return LIBRT_DEFAULT_DATA_DIR;
}

unsigned thread_count() { return std::max(1u, std::thread::hardware_concurrency()); }

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
    std::vector<Ray> miss;  ///< the incoherent directions from outside the box, pointing away
    bool headline = false;  ///< gets the full matrix (any-hit, primary, all cores)
};

std::vector<std::shared_ptr<Workload>> make_workloads() {
    std::vector<std::shared_ptr<Workload>> out;
    auto add = [&](std::string name, TriangleMesh mesh, bool headline) {
        auto w = std::make_shared<Workload>();
        w->name = std::move(name);
        w->mesh = std::move(mesh);
        w->headline = headline;
        normalise(w->mesh);
        const BBox box = w->mesh.bounds();
        w->incoherent = librt::testing::incoherent_rays(box, kIncoherentRays, 42);
        // Origins two box diagonals from the centre along the direction: the ray points away
        // from a box it starts outside, so it misses every child of the root.
        w->miss.reserve(w->incoherent.size());
        const float reach = 2.0f * glm::length(box.diagonal());
        for (const Ray& r : w->incoherent)
            w->miss.push_back({box.center() + reach * glm::normalize(r.direction), r.direction});
        if (headline)
            w->primary =
                librt::testing::primary_rays(box, kPrimaryResolution, kPrimaryResolution, 40.0f);
        out.push_back(std::move(w));
    };
    for (const std::size_t target : {1'000u, 10'000u, 100'000u, 1'000'000u})
        add("teapot" + std::to_string(target / 1000) + "k", make_teapot_with_triangles(target),
            target == 1'000'000u);
    for (const char* file : {"stanford-bunny.obj", "stanford-dragon.obj"}) {
        const fs::path path = data_dir() / file;
        if (!fs::is_regular_file(path)) {
            std::cerr << "librt_bench: " << path << " not found, its rows are skipped "
                      << "(set LIBRT_DATA_DIR)\n";
            continue;
        }
        add(fs::path(file).stem().string().substr(9), load_obj(path), true);  // "bunny", "dragon"
    }
    return out;
}

/// The binary BVH through the generic traverse<> and the watertight test: what
/// TriangleBvh was before the wide BVH, kept as a reference point.
class BinaryTriangleBvh {
public:
    BinaryTriangleBvh(const TriangleMesh& mesh, BvhBuilder builder) {
        std::vector<BBox> boxes(mesh.triangle_count());
        std::vector<glm::vec3> centers(mesh.triangle_count());
        for (std::size_t i = 0; i < boxes.size(); ++i) {
            boxes[i] = bounds(mesh.triangle(i));
            centers[i] = boxes[i].center();
        }
        bvh_ = build_bvh(builder, boxes, centers);
        triangles_.resize(boxes.size());
        for (std::size_t s = 0; s < boxes.size(); ++s)
            triangles_[s] = mesh.triangle(bvh_.prim_indices[s]);
    }
    [[nodiscard]] PrimitiveHit intersect(const Ray& ray) const {
        Ray r = ray;
        const WatertightRay w = prepare_watertight(ray);
        PrimitiveHit hit;
        traverse<false>(bvh_, r, [&](std::uint32_t slot, Ray& cur) {
            const auto h = librt::intersect(triangles_[slot], w, cur.t_min, cur.t_max);
            if (!h) return false;
            cur.t_max = h->t;
            hit = {h->t, h->u, h->v, bvh_.prim_indices[slot]};
            return true;
        });
        return hit;
    }
    [[nodiscard]] bool occluded(const Ray& ray) const {
        Ray r = ray;
        const WatertightRay w = prepare_watertight(ray);
        return traverse<true>(bvh_, r, [&](std::uint32_t slot, Ray& cur) {
            return librt::intersect(triangles_[slot], w, cur.t_min, cur.t_max).has_value();
        });
    }
    [[nodiscard]] std::size_t memory_bytes() const {
        return bvh_.memory_bytes() + triangles_.size() * sizeof(Triangle);
    }

private:
    Bvh bvh_;
    std::vector<Triangle> triangles_;
};

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

enum class Query { Closest, Any };

template <class Engine>
std::size_t trace_range(const Engine& engine, const Ray* rays, std::size_t count, Query query) {
    std::size_t hits = 0;
    if (query == Query::Any) {
        for (std::size_t i = 0; i < count; ++i) hits += engine.occluded(rays[i]);
    } else {
        for (std::size_t i = 0; i < count; ++i) hits += engine.intersect(rays[i]).valid();
    }
    return hits;
}

/// Every counter any row has: the CSV reporter wants one set of columns for the run, so
/// a row gets 0 for those that do not apply to it.
constexpr const char* kCounters[] = {
    "Mrays",         "librt_Mrays",   "embree_Mrays", "ratio",       "librt_ms", "embree_ms",
    "librt_B/tri",   "embree_B/tri",  "hit%",         "tris",        "threads",  "librt1_Mrays",
    "embree1_Mrays", "ratio_embree1", "ratio_librt1", "ratio_single"};

void complete_counters(benchmark::State& state) {
    for (const char* key : kCounters)
        if (state.counters.find(key) == state.counters.end()) state.counters[key] = 0.0;
}

/// One engine alone, single thread (the naive scan and the binary BVHs): the framework
/// times the calling thread's CPU time.
template <class Engine>
void trace_single(benchmark::State& state, const Engine& engine, const std::vector<Ray>& rays,
                  std::size_t count, Query query, double tris) {
    count = std::min(count, rays.size());
    std::size_t hits = 0;
    for (auto _ : state) {
        hits += trace_range(engine, rays.data(), count, query);
        benchmark::DoNotOptimize(hits);
    }
    state.counters["Mrays"] = benchmark::Counter(static_cast<double>(count) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
    state.counters["hit%"] = 100.0 * static_cast<double>(hits) /
                             (static_cast<double>(count) * static_cast<double>(state.iterations()));
    state.counters["tris"] = tris;
    complete_counters(state);
}

/// librt and (when present) Embree on the same rays, chunk by chunk, on `threads` threads
/// (1 = the calling thread). Each engine's rate is rays / (its summed thread CPU time /
/// threads); the iteration time is both engines' (manual time).
template <class A, class B>
void trace_pair(benchmark::State& state, const A& a, const B* b, const std::vector<Ray>& rays,
                Query query, double tris, unsigned threads) {
    constexpr std::size_t kChunk = 1u << 15;
    const std::size_t chunks = (rays.size() + kChunk - 1) / kChunk;
    double cpu_a = 0.0, cpu_b = 0.0;
    std::size_t hits_a = 0, hits_b = 0;
    for (auto _ : state) {
        std::atomic<std::size_t> next{0};
        std::vector<double> ta(threads, 0.0), tb(threads, 0.0);
        std::vector<std::size_t> ha(threads, 0), hb(threads, 0);
        auto work = [&](unsigned t) {
            for (;;) {
                const std::size_t k = next.fetch_add(1);
                if (k >= chunks) break;
                const Ray* first = rays.data() + k * kChunk;
                const std::size_t n = std::min(kChunk, rays.size() - k * kChunk);
                auto run_a = [&] {
                    const double start = thread_cpu_seconds();
                    ha[t] += trace_range(a, first, n, query);
                    ta[t] += thread_cpu_seconds() - start;
                };
                auto run_b = [&] {
                    if (!b) return;
                    const double start = thread_cpu_seconds();
                    hb[t] += trace_range(*b, first, n, query);
                    tb[t] += thread_cpu_seconds() - start;
                };
                if (k % 2 == 0) {
                    run_a();
                    run_b();
                } else {
                    run_b();
                    run_a();
                }
            }
        };
        std::vector<std::thread> helpers;
        for (unsigned t = 1; t < threads; ++t) helpers.emplace_back(work, t);
        work(0);
        for (std::thread& t : helpers) t.join();
        double iteration = 0.0;
        for (unsigned t = 0; t < threads; ++t) {
            cpu_a += ta[t];
            cpu_b += tb[t];
            hits_a += ha[t];
            hits_b += hb[t];
            iteration += ta[t] + tb[t];
        }
        state.SetIterationTime(iteration / threads);
    }
    const double rays_total =
        static_cast<double>(rays.size()) * static_cast<double>(state.iterations());
    const double librt = rays_total / (cpu_a / threads) * 1e-6;
    state.counters["librt_Mrays"] = librt;
    state.counters["hit%"] = 100.0 * static_cast<double>(hits_a) / rays_total;
    if (b) {
        const double embree = rays_total / (cpu_b / threads) * 1e-6;
        state.counters["embree_Mrays"] = embree;
        state.counters["ratio"] = librt / embree;
        if (hits_a != hits_b)  // the engines may differ on rays grazing an edge, rarely
            state.counters["embree_hit%"] = 100.0 * static_cast<double>(hits_b) / rays_total;
    }
    state.counters["tris"] = tris;
    state.counters["threads"] = threads;
    complete_counters(state);
    state.counters.erase("embree_hit%");  // keep the CSV's columns fixed
}

/// The stream rows (<mesh>/librt_stream_vs_embree/<rays>/1t): four engines on the same chunks
/// of rays, on the calling thread, the order rotated from chunk to chunk: librt's stream
/// (TriangleBvh::intersect(rays, hits) / occluded(rays, blocked)), librt's single rays,
/// Embree's stream (rtcIntersect1M / rtcOccluded1M, the context flagged coherent for primary
/// rays, else incoherent) and Embree's single rays. Counters: librt_Mrays and embree_Mrays
/// are the streams, librt1_Mrays and embree1_Mrays the single rays; ratio = librt stream /
/// Embree stream, ratio_embree1 = librt stream / Embree single, ratio_librt1 = librt stream /
/// librt single, ratio_single = librt single / Embree single (the librt_vs_embree row's
/// ratio, here in the same minutes). The row fails if librt's stream and single rays disagree
/// on a hit.
void trace_stream_row(benchmark::State& state, const TriangleBvh& librt,
                      const bench::EmbreeScene& embree, const std::vector<Ray>& rays, Query query,
                      bool coherent, double tris) {
    constexpr std::size_t kChunk = 1u << 15;
    const std::size_t chunks = (rays.size() + kChunk - 1) / kChunk;
    // Each engine's answers kept apart, compared after the chunk (untimed).
    std::vector<PrimitiveHit> hits(kChunk), single_hits(kChunk), embree_hits(kChunk);
    std::vector<std::uint8_t> blocked(kChunk), single_blocked(kChunk), embree_blocked(kChunk);
    double cpu[4] = {0, 0, 0, 0};
    std::size_t hit_count[4] = {0, 0, 0, 0};
    bool mismatch = false;
    std::size_t rotation = 0;
    for (auto _ : state) {
        double iteration = 0.0;
        for (std::size_t k = 0; k < chunks; ++k) {
            const Ray* first = rays.data() + k * kChunk;
            const std::size_t n = std::min(kChunk, rays.size() - k * kChunk);
            const std::span<const Ray> chunk(first, n);
            auto run = [&](int engine) {
                const double start = thread_cpu_seconds();
                std::size_t h = 0;
                switch (engine) {
                    case 0:
                        if (query == Query::Any) {
                            librt.occluded(chunk, std::span(blocked.data(), n));
                            for (std::size_t i = 0; i < n; ++i) h += blocked[i];
                        } else {
                            librt.intersect(chunk, std::span(hits.data(), n));
                            for (std::size_t i = 0; i < n; ++i) h += hits[i].valid();
                        }
                        break;
                    case 1:
                        if (query == Query::Any) {
                            for (std::size_t i = 0; i < n; ++i)
                                h += single_blocked[i] = librt.occluded(first[i]) ? 1 : 0;
                        } else {
                            for (std::size_t i = 0; i < n; ++i)
                                h += (single_hits[i] = librt.intersect(first[i])).valid();
                        }
                        break;
                    case 2:
                        h = query == Query::Any
                                ? embree.occluded_stream(chunk, std::span(embree_blocked.data(), n),
                                                         coherent)
                                : embree.intersect_stream(chunk, std::span(embree_hits.data(), n),
                                                          coherent);
                        break;
                    default:
                        h = trace_range(embree, first, n, query);
                }
                const double seconds = thread_cpu_seconds() - start;
                cpu[engine] += seconds;
                iteration += seconds;
                hit_count[engine] += h;
            };
            const int first_engine = static_cast<int>(rotation++ % 4);
            for (int e = 0; e < 4; ++e) run((first_engine + e) % 4);
            // librt's stream against its single rays, ray by ray, bit for bit.
            for (std::size_t i = 0; i < n; ++i) {
                if (query == Query::Any) {
                    mismatch |= blocked[i] != single_blocked[i];
                } else {
                    const PrimitiveHit& a = hits[i];
                    const PrimitiveHit& b = single_hits[i];
                    mismatch |=
                        std::bit_cast<std::uint32_t>(a.t) != std::bit_cast<std::uint32_t>(b.t) ||
                        std::bit_cast<std::uint32_t>(a.u) != std::bit_cast<std::uint32_t>(b.u) ||
                        std::bit_cast<std::uint32_t>(a.v) != std::bit_cast<std::uint32_t>(b.v) ||
                        a.primitive_id != b.primitive_id;
                }
            }
        }
        state.SetIterationTime(iteration);
    }
    if (mismatch) {
        state.SkipWithError("librt's stream and single rays disagree");
        return;
    }
    const double rays_total =
        static_cast<double>(rays.size()) * static_cast<double>(state.iterations());
    auto rate = [&](int engine) { return rays_total / cpu[engine] * 1e-6; };
    state.counters["librt_Mrays"] = rate(0);
    state.counters["librt1_Mrays"] = rate(1);
    state.counters["embree_Mrays"] = rate(2);
    state.counters["embree1_Mrays"] = rate(3);
    state.counters["ratio"] = rate(0) / rate(2);
    state.counters["ratio_embree1"] = rate(0) / rate(3);
    state.counters["ratio_librt1"] = rate(0) / rate(1);
    state.counters["ratio_single"] = rate(1) / rate(3);
    state.counters["hit%"] = 100.0 * static_cast<double>(hit_count[0]) / rays_total;
    if (hit_count[0] != hit_count[1]) {
        state.SkipWithError("librt's stream and single rays hit different counts");
        return;
    }
    state.counters["tris"] = tris;
    state.counters["threads"] = 1;
    complete_counters(state);
}

double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

/// An engine built on first use, so that a --benchmark_filter run builds only what it
/// traces (the benchmarks run one after another on the main thread).
template <class Engine>
class Lazy {
public:
    explicit Lazy(const TriangleMesh* mesh, std::optional<BvhBuilder> builder = std::nullopt)
        : mesh_(mesh), builder_(builder) {}
    const Engine& operator*() {
        if (!engine_) {
            if constexpr (std::is_constructible_v<Engine, const TriangleMesh&, BvhBuilder>)
                engine_ = std::make_unique<Engine>(*mesh_, builder_.value_or(BvhBuilder::Sah));
            else
                engine_ = std::make_unique<Engine>(*mesh_);
        }
        return *engine_;
    }

private:
    const TriangleMesh* mesh_;
    std::optional<BvhBuilder> builder_;
    std::unique_ptr<Engine> engine_;
};

/// Which rays a row traces, and how.
struct RowKind {
    const char* rays;  ///< "incoherent", "anyhit" or "primary"
    Query query;
    bool parallel;
};

/// A build row of one binary builder (wall time; memory of the BVH and its triangles).
void register_binary_build(const std::shared_ptr<Workload>& w, const char* name,
                           BvhBuilder builder) {
    const double tris = static_cast<double>(w->mesh.triangle_count());
    benchmark::RegisterBenchmark((w->name + "/" + name + "/build").c_str(),
                                 [=](benchmark::State& s) {
                                     std::size_t bytes = 0;
                                     for (auto _ : s) {
                                         bytes = BinaryTriangleBvh(w->mesh, builder).memory_bytes();
                                         benchmark::DoNotOptimize(bytes);
                                     }
                                     s.counters["librt_B/tri"] = static_cast<double>(bytes) / tris;
                                     s.counters["tris"] = tris;
                                     complete_counters(s);
                                 })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime();
}

/// Embree at high build quality, as an engine of its own for Lazy<> and the rows.
class EmbreeHqScene : public bench::EmbreeScene {
public:
    explicit EmbreeHqScene(const TriangleMesh& mesh)
        : EmbreeScene(mesh, bench::EmbreeQuality::High) {}
};

/// Embree with RTC_SCENE_FLAG_ROBUST (default build quality), as an engine of its own.
class EmbreeRobustScene : public bench::EmbreeScene {
public:
    explicit EmbreeRobustScene(const TriangleMesh& mesh)
        : EmbreeScene(mesh, bench::EmbreeQuality::Robust) {}
};

/// librt's build beside Embree's at `quality` (alternating which goes first), wall time each.
void register_pair_build(const std::shared_ptr<Workload>& w, const std::string& engines,
                         bench::EmbreeQuality quality = bench::EmbreeQuality::Default) {
    const double tris = static_cast<double>(w->mesh.triangle_count());
    benchmark::RegisterBenchmark(
        (w->name + "/" + engines + "/build").c_str(),
        [=](benchmark::State& s) {
            double wall_a = 0.0, wall_b = 0.0;
            std::size_t bytes_a = 0, bytes_b = 0;
            bool a_first = true;
            for (auto _ : s) {
                auto run_a = [&] {
                    const double start = wall_seconds();
                    bytes_a = TriangleBvh(w->mesh).memory_bytes();
                    wall_a += wall_seconds() - start;
                };
                auto run_b = [&] {
                    if (!bench::embree_available()) return;
                    const double start = wall_seconds();
                    bytes_b = bench::EmbreeScene(w->mesh, quality).memory_bytes();
                    wall_b += wall_seconds() - start;
                };
                const double start = wall_seconds();
                if (a_first) {
                    run_a();
                    run_b();
                } else {
                    run_b();
                    run_a();
                }
                a_first = !a_first;
                s.SetIterationTime(wall_seconds() - start);
            }
            const double n = static_cast<double>(s.iterations());
            s.counters["librt_ms"] = 1e3 * wall_a / n;
            s.counters["librt_B/tri"] = static_cast<double>(bytes_a) / tris;
            if (bench::embree_available()) {
                s.counters["embree_ms"] = 1e3 * wall_b / n;
                s.counters["embree_B/tri"] = static_cast<double>(bytes_b) / tris;
                s.counters["ratio"] = wall_a / wall_b;
            }
            s.counters["tris"] = tris;
            complete_counters(s);
        })
        ->Unit(benchmark::kMillisecond)
        ->UseManualTime();
}

void register_all(const std::vector<std::shared_ptr<Workload>>& workloads) {
    const bool have_embree = bench::embree_available();
    const std::string engines = have_embree ? "librt_vs_embree" : "librt";
    for (const auto& w : workloads) {
        const TriangleMesh* mesh = &w->mesh;
        const double tris = static_cast<double>(mesh->triangle_count());
        register_binary_build(w, "median", BvhBuilder::Median);
        register_binary_build(w, "sah", BvhBuilder::Sah);
        register_pair_build(w, engines);
        if (have_embree) register_pair_build(w, "librt_vs_embree_hq", bench::EmbreeQuality::High);

        // The slow engines: incoherent closest hit on one thread, on a prefix of the rays.
        auto single = [&](const char* name, auto engine, std::size_t count) {
            benchmark::RegisterBenchmark((w->name + "/" + name + "/incoherent/1t").c_str(),
                                         [=](benchmark::State& s) {
                                             trace_single(s, **engine, w->incoherent, count,
                                                          Query::Closest, tris);
                                         })
                ->Unit(benchmark::kMillisecond);
        };
        if (w->mesh.triangle_count() <= 100'000)
            single("naive", std::make_shared<Lazy<TriangleList>>(mesh), kNaiveRays);
        single("median", std::make_shared<Lazy<BinaryTriangleBvh>>(mesh, BvhBuilder::Median),
               kBinaryRays);
        single("sah", std::make_shared<Lazy<BinaryTriangleBvh>>(mesh, BvhBuilder::Sah),
               kBinaryRays);

        auto librt = std::make_shared<Lazy<TriangleBvh>>(mesh, BvhBuilder::Sah);
        auto embree = std::make_shared<Lazy<bench::EmbreeScene>>(mesh);
        auto embree_hq = std::make_shared<Lazy<EmbreeHqScene>>(mesh);
        auto embree_robust = std::make_shared<Lazy<EmbreeRobustScene>>(mesh);
        const RowKind kinds[] = {
            {"incoherent", Query::Closest, false}, {"incoherent", Query::Closest, true},
            {"anyhit", Query::Any, false},         {"anyhit", Query::Any, true},
            {"primary", Query::Closest, false},    {"primary", Query::Closest, true},
            {"miss", Query::Closest, false}};
        for (const RowKind& kind : kinds) {
            const std::string ray_kind = kind.rays;
            if (!w->headline && (kind.parallel || ray_kind == "primary")) continue;
            if (kind.parallel && thread_count() == 1) continue;
            const std::vector<Ray>* rays = ray_kind == "primary" ? &w->primary
                                           : ray_kind == "miss"  ? &w->miss
                                                                 : &w->incoherent;
            const unsigned threads = kind.parallel ? thread_count() : 1u;
            const std::string suffix =
                std::string("/") + kind.rays + "/" + std::to_string(threads) + "t";
            const Query query = kind.query;
            benchmark::RegisterBenchmark((w->name + "/" + engines + suffix).c_str(),
                                         [=](benchmark::State& s) {
                                             const TriangleBvh& a = **librt;
                                             const bench::EmbreeScene* b =
                                                 have_embree ? &**embree : nullptr;
                                             trace_pair(s, a, b, *rays, query, tris, threads);
                                         })
                ->Unit(benchmark::kMillisecond)
                ->UseManualTime();
            if (!have_embree) continue;
            // The same librt rays beside another Embree scene: high build quality (not on the
            // miss rays, which never reach below the root), and robust mode (1t rows).
            auto pair_row = [&](const std::string& engines_name, auto scene) {
                benchmark::RegisterBenchmark((w->name + "/" + engines_name + suffix).c_str(),
                                             [=](benchmark::State& s) {
                                                 trace_pair(s, **librt, &**scene, *rays, query,
                                                            tris, threads);
                                             })
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime();
            };
            if (ray_kind != "miss") pair_row("librt_vs_embree_hq", embree_hq);
            if (!kind.parallel) pair_row("librt_vs_embree_robust", embree_robust);
            if (!kind.parallel && ray_kind != "miss") {
                const bool coherent = ray_kind == "primary";
                benchmark::RegisterBenchmark((w->name + "/librt_stream_vs_embree" + suffix).c_str(),
                                             [=](benchmark::State& s) {
                                                 trace_stream_row(s, **librt, **embree, *rays,
                                                                  query, coherent, tris);
                                             })
                    ->Unit(benchmark::kMillisecond)
                    ->UseManualTime();
            }
        }
    }
}

/// The console reporter, also keeping each row's counters for the summary table.
class SummaryReporter : public benchmark::ConsoleReporter {
public:
    void ReportRuns(const std::vector<Run>& runs) override {
        ConsoleReporter::ReportRuns(runs);
        for (const Run& run : runs) {
            if (run.error_occurred) continue;
            const bool is_median =
                run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
            if (run.run_type == Run::RT_Aggregate && !is_median) continue;
            Row& row = rows_[run.run_name.function_name];
            if (row.median && !is_median) continue;  // a median beats single runs
            row.median = is_median;
            for (const auto& [key, counter] : run.counters) row.counters[key] = counter.value;
        }
    }

    /// Prints librt beside Embree (and the binary BVHs for context) for every mesh.
    void print_summary(const std::vector<std::shared_ptr<Workload>>& workloads) const {
        auto get = [&](const std::string& name, const char* key) -> std::optional<double> {
            const auto it = rows_.find(name);
            if (it == rows_.end()) return std::nullopt;
            const auto c = it->second.counters.find(key);
            if (c == it->second.counters.end() || c->second == 0.0) return std::nullopt;
            return c->second;
        };
        auto cell = [](std::optional<double> v, const char* fmt) {
            char buf[32];
            if (!v) return std::string("-");
            std::snprintf(buf, sizeof buf, fmt, *v);
            return std::string(buf);
        };
        const bool have_embree = bench::embree_available();
        const std::string engines = have_embree ? "librt_vs_embree" : "librt";
        const std::string mt = std::to_string(thread_count()) + "t";
        std::printf(
            "\nSummary: Mrays/s (1t: one thread's CPU time; %s: per %u dedicated cores), "
            "medians when repeated%s\n",
            mt.c_str(), thread_count(),
            have_embree ? "" : "\n  Embree rows are missing: librt_bench was built without Embree");
        std::printf("%-12s %-11s %-4s %9s %9s %9s %9s %7s %9s %7s %9s %7s\n", "mesh", "rays", "thr",
                    "median", "sah", "librt", "embree", "ratio", "embree_hq", "ratio", "robust",
                    "ratio");
        for (const auto& w : workloads)
            for (const char* rays : {"incoherent", "anyhit", "primary", "miss"})
                for (const std::string& threads : {std::string("1t"), mt}) {
                    const std::string pair = w->name + "/" + engines + "/" + rays + "/" + threads;
                    const auto librt = get(pair, "librt_Mrays");
                    if (!librt) continue;
                    auto single = [&](const char* engine) {
                        return get(w->name + "/" + engine + "/" + rays + "/" + threads, "Mrays");
                    };
                    const std::string hq = w->name + "/librt_vs_embree_hq/" + rays + "/" + threads;
                    const std::string rb =
                        w->name + "/librt_vs_embree_robust/" + rays + "/" + threads;
                    std::printf("%-12s %-11s %-4s %9s %9s %9s %9s %7s %9s %7s %9s %7s\n",
                                w->name.c_str(), rays, threads.c_str(),
                                cell(single("median"), "%.3f").c_str(),
                                cell(single("sah"), "%.3f").c_str(), cell(librt, "%.3f").c_str(),
                                cell(get(pair, "embree_Mrays"), "%.3f").c_str(),
                                cell(get(pair, "ratio"), "%.2f").c_str(),
                                cell(get(hq, "embree_Mrays"), "%.3f").c_str(),
                                cell(get(hq, "ratio"), "%.2f").c_str(),
                                cell(get(rb, "embree_Mrays"), "%.3f").c_str(),
                                cell(get(rb, "ratio"), "%.2f").c_str());
                }
        if (have_embree) {
            std::printf(
                "\nRay streams (1t, Mrays/s; librt's stream over Embree's stream, Embree's "
                "single rays and librt's single rays)\n");
            std::printf("%-12s %-11s %9s %9s %9s %9s %8s %8s %8s\n", "mesh", "rays", "librt_str",
                        "librt_1", "embr_str", "embree_1", "/e_str", "/e_1", "/l_1");
            for (const auto& w : workloads)
                for (const char* rays : {"incoherent", "anyhit", "primary"}) {
                    const std::string row =
                        w->name + "/librt_stream_vs_embree/" + std::string(rays) + "/1t";
                    if (!get(row, "librt_Mrays")) continue;
                    std::printf("%-12s %-11s %9s %9s %9s %9s %8s %8s %8s\n", w->name.c_str(), rays,
                                cell(get(row, "librt_Mrays"), "%.3f").c_str(),
                                cell(get(row, "librt1_Mrays"), "%.3f").c_str(),
                                cell(get(row, "embree_Mrays"), "%.3f").c_str(),
                                cell(get(row, "embree1_Mrays"), "%.3f").c_str(),
                                cell(get(row, "ratio"), "%.2f").c_str(),
                                cell(get(row, "ratio_embree1"), "%.2f").c_str(),
                                cell(get(row, "ratio_librt1"), "%.2f").c_str());
                }
        }
        std::printf("\n%-12s %10s %10s %7s %11s %12s %7s %10s %7s %9s\n", "mesh", "librt ms",
                    "embree ms", "ratio", "librt B/tri", "embree B/tri", "ratio", "HQ ms", "ratio",
                    "HQ B/tri");
        for (const auto& w : workloads) {
            const std::string build = w->name + "/" + engines + "/build";
            const auto lb = get(build, "librt_B/tri"), eb = get(build, "embree_B/tri");
            if (!get(build, "librt_ms")) continue;
            std::optional<double> rb;
            if (lb && eb) rb = *lb / *eb;
            const std::string hq = w->name + "/librt_vs_embree_hq/build";
            std::printf("%-12s %10s %10s %7s %11s %12s %7s %10s %7s %9s\n", w->name.c_str(),
                        cell(get(build, "librt_ms"), "%.1f").c_str(),
                        cell(get(build, "embree_ms"), "%.1f").c_str(),
                        cell(get(build, "ratio"), "%.2f").c_str(), cell(lb, "%.1f").c_str(),
                        cell(eb, "%.1f").c_str(), cell(rb, "%.2f").c_str(),
                        cell(get(hq, "embree_ms"), "%.1f").c_str(),
                        cell(get(hq, "ratio"), "%.2f").c_str(),
                        cell(get(hq, "embree_B/tri"), "%.1f").c_str());
        }
        double load[3] = {0, 0, 0};
        if (getloadavg(load, 3) == 3)
            std::printf("\nload average at the end of the run: %.2f %.2f %.2f\n", load[0], load[1],
                        load[2]);
    }

private:
    struct Row {
        std::map<std::string, double> counters;
        bool median = false;  ///< from the median aggregate rather than a single run
    };
    std::map<std::string, Row> rows_;
};

}  // namespace

int main(int argc, char** argv) {
    benchmark::Initialize(&argc, argv);
    if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
    if (!bench::embree_available())
        std::cerr << "librt_bench: built without Embree (find_package(embree 3) failed): "
                     "Embree rows are missing\n";
    const auto workloads = make_workloads();
    register_all(workloads);
    SummaryReporter reporter;
    benchmark::RunSpecifiedBenchmarks(&reporter);
    reporter.print_summary(workloads);
    benchmark::Shutdown();
    return 0;
}
