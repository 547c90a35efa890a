// BVH microbenchmarks: librt against Embree 3 on the same meshes and rays, from one run.
//
// Engines: "naive" (TriangleList, small meshes and few rays only), "median" and "sah"
// (the binary BVHs through the generic traverse<>), "librt" (TriangleBvh, the fast path
// the renderer uses) and "embree" (rtcIntersect1 / rtcOccluded1, when CMake found it).
// Rows are named <mesh>/<engine>/<rays>/<threads>, or <mesh>/<engine>/build.
//
// Rays: "incoherent" (closest hit), "anyhit" (the same rays through occluded()) and
// "primary" (1024x1024 pinhole), see tests/ray_sets.h. "1t" rows trace on the calling
// thread and report rays / thread CPU time; "<N>t" rows split the rays over N
// std::threads (N = hardware threads) and report rays / (summed thread CPU time / N),
// i.e. the rate of N dedicated cores, with the wall-clock rate as "wall_Mrays". Builds
// report wall time (Embree and librt build on all cores) and memory per triangle.
//
// After the run a summary table prints each librt row beside its Embree row with their
// ratio (medians when --benchmark_repetitions is given).
//
// Run: ./build/release/bench/librt_bench [--benchmark_filter=bunny] [--benchmark_repetitions=3]
// Meshes are centred and scaled to a bounding-box diagonal of 100, as in the reference
// figures of ../shared/data/README.md.

#include <librt/accel/bvh_builder.h>
#include <librt/accel/bvh_traversal.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/geometry/mesh.h>
#include <librt/geometry/procedural.h>
#include <librt/io/obj.h>

#include <benchmark/benchmark.h>

#include "../tests/ray_sets.h"
#include "embree_scene.h"

#include <glm/geometric.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>
#include <optional>
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
        if (headline)
            w->primary = librt::testing::primary_rays(box, kPrimaryResolution, kPrimaryResolution, 40.0f);
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
        for (std::size_t s = 0; s < boxes.size(); ++s) triangles_[s] = mesh.triangle(bvh_.prim_indices[s]);
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

void set_ray_counters(benchmark::State& state, std::size_t count, std::size_t hits,
                      double tris) {
    state.counters["Mrays"] = benchmark::Counter(static_cast<double>(count) * 1e-6,
                                                 benchmark::Counter::kIsIterationInvariantRate);
    state.counters["hit%"] = 100.0 * static_cast<double>(hits) /
                             (static_cast<double>(count) * static_cast<double>(state.iterations()));
    state.counters["tris"] = tris;
}

/// Single thread: the framework times the calling thread's CPU time.
template <class Engine>
void trace_single(benchmark::State& state, const Engine& engine, const std::vector<Ray>& rays,
                  std::size_t count, Query query, double tris) {
    count = std::min(count, rays.size());
    std::size_t hits = 0;
    for (auto _ : state) {
        hits += trace_range(engine, rays.data(), count, query);
        benchmark::DoNotOptimize(hits);
    }
    set_ray_counters(state, count, hits, tris);
}

/// All cores: threads take chunks of rays from a shared counter; the iteration time is
/// the threads' mean CPU time (what N dedicated cores would take), wall time aside.
template <class Engine>
void trace_parallel(benchmark::State& state, const Engine& engine, const std::vector<Ray>& rays,
                    Query query, double tris) {
    constexpr std::size_t kChunk = 4096;
    const unsigned n = thread_count();
    std::size_t hits = 0;
    double wall_total = 0.0;
    for (auto _ : state) {
        std::atomic<std::size_t> next{0};
        std::atomic<std::size_t> iteration_hits{0};
        std::vector<double> cpu(n, 0.0);
        auto work = [&](unsigned t) {
            const double start = thread_cpu_seconds();
            std::size_t h = 0;
            for (;;) {
                const std::size_t begin = next.fetch_add(kChunk);
                if (begin >= rays.size()) break;
                h += trace_range(engine, rays.data() + begin, std::min(kChunk, rays.size() - begin), query);
            }
            iteration_hits += h;
            cpu[t] = thread_cpu_seconds() - start;
        };
        const auto wall_start = std::chrono::steady_clock::now();
        std::vector<std::thread> threads;
        for (unsigned t = 1; t < n; ++t) threads.emplace_back(work, t);
        work(0);
        for (std::thread& t : threads) t.join();
        wall_total += std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
        double cpu_sum = 0.0;
        for (const double c : cpu) cpu_sum += c;
        state.SetIterationTime(cpu_sum / n);
        hits += iteration_hits.load();
    }
    set_ray_counters(state, rays.size(), hits, tris);
    state.counters["wall_Mrays"] = static_cast<double>(rays.size()) * 1e-6 *
                                   static_cast<double>(state.iterations()) / wall_total;
    state.counters["threads"] = n;
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

/// Registers one trace row of one engine on one workload.
template <class Engine>
void register_trace(const std::shared_ptr<Workload>& w, const std::string& engine_name,
                    std::shared_ptr<Lazy<Engine>> engine, const RowKind& kind, std::size_t count) {
    const double tris = static_cast<double>(w->mesh.triangle_count());
    const std::vector<Ray>* rays = std::string(kind.rays) == "primary" ? &w->primary : &w->incoherent;
    const std::string threads = kind.parallel ? std::to_string(thread_count()) + "t" : "1t";
    const std::string name = w->name + "/" + engine_name + "/" + kind.rays + "/" + threads;
    const Query query = kind.query;
    if (kind.parallel) {
        benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& s) {
            trace_parallel(s, **engine, *rays, query, tris);
        })->Unit(benchmark::kMillisecond)->UseManualTime();
    } else {
        benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& s) {
            trace_single(s, **engine, *rays, count, query, tris);
        })->Unit(benchmark::kMillisecond);
    }
}

/// Registers a build row: `make` builds the engine and returns its memory in bytes.
template <class Make>
void register_build(const std::shared_ptr<Workload>& w, const std::string& engine_name, Make make) {
    const double tris = static_cast<double>(w->mesh.triangle_count());
    benchmark::RegisterBenchmark((w->name + "/" + engine_name + "/build").c_str(),
                                 [=](benchmark::State& s) {
                                     std::size_t bytes = 0;
                                     for (auto _ : s) {
                                         bytes = make();
                                         benchmark::DoNotOptimize(bytes);
                                     }
                                     s.counters["bytes/tri"] = static_cast<double>(bytes) / tris;
                                     s.counters["tris"] = tris;
                                 })
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MeasureProcessCPUTime();
}

void register_all(const std::vector<std::shared_ptr<Workload>>& workloads) {
    for (const auto& w : workloads) {
        // Rows that are compared sit next to each other, so they run close in time on a
        // machine whose load drifts: the builds, then each ray set engine by engine.
        const TriangleMesh* mesh = &w->mesh;
        register_build(w, "median", [mesh] { return BinaryTriangleBvh(*mesh, BvhBuilder::Median).memory_bytes(); });
        register_build(w, "sah", [mesh] { return BinaryTriangleBvh(*mesh, BvhBuilder::Sah).memory_bytes(); });
        register_build(w, "librt", [mesh] { return TriangleBvh(*mesh).memory_bytes(); });
        if (bench::embree_available())
            register_build(w, "embree", [mesh] { return bench::EmbreeScene(*mesh).memory_bytes(); });

        auto naive = std::make_shared<Lazy<TriangleList>>(mesh);
        auto median = std::make_shared<Lazy<BinaryTriangleBvh>>(mesh, BvhBuilder::Median);
        auto sah = std::make_shared<Lazy<BinaryTriangleBvh>>(mesh, BvhBuilder::Sah);
        auto librt = std::make_shared<Lazy<TriangleBvh>>(mesh, BvhBuilder::Sah);
        auto embree = std::make_shared<Lazy<bench::EmbreeScene>>(mesh);
        const RowKind kinds[] = {{"incoherent", Query::Closest, false}, {"incoherent", Query::Closest, true},
                                 {"anyhit", Query::Any, false},         {"anyhit", Query::Any, true},
                                 {"primary", Query::Closest, false},    {"primary", Query::Closest, true}};
        for (const RowKind& kind : kinds) {
            const bool first = &kind == &kinds[0];
            if (!first && !w->headline) break;
            if (first) {
                // The slow engines only on incoherent rays, single thread, on a prefix.
                if (w->mesh.triangle_count() <= 100'000) register_trace(w, "naive", naive, kind, kNaiveRays);
                register_trace(w, "median", median, kind, kBinaryRays);
                register_trace(w, "sah", sah, kind, kBinaryRays);
            }
            register_trace(w, "librt", librt, kind, kIncoherentRays);
            if (bench::embree_available()) register_trace(w, "embree", embree, kind, kIncoherentRays);
        }
    }
}

/// The console reporter, also keeping each row's figures for the summary table.
class SummaryReporter : public benchmark::ConsoleReporter {
public:
    struct Figures {
        double mrays = 0.0, ms = 0.0, bytes_per_tri = 0.0;
        bool median = false;  ///< from the median aggregate rather than a single run
    };

    void ReportRuns(const std::vector<Run>& runs) override {
        ConsoleReporter::ReportRuns(runs);
        for (const Run& run : runs) {
            if (run.error_occurred) continue;
            const bool is_median = run.run_type == Run::RT_Aggregate && run.aggregate_name == "median";
            if (run.run_type == Run::RT_Aggregate && !is_median) continue;
            Figures& f = rows_[run.run_name.function_name];
            if (f.median && !is_median) continue;
            f.median = is_median;
            auto counter = [&](const char* key) {
                const auto it = run.counters.find(key);
                return it == run.counters.end() ? 0.0 : it->second.value;
            };
            f.mrays = counter("Mrays");
            f.bytes_per_tri = counter("bytes/tri");
            f.ms = run.GetAdjustedRealTime();  // rows use milliseconds
        }
    }

    /// Prints librt beside Embree (and the binary BVHs for context) for every mesh.
    void print_summary(const std::vector<std::shared_ptr<Workload>>& workloads) const {
        auto find = [&](const std::string& name) -> std::optional<Figures> {
            const auto it = rows_.find(name);
            if (it == rows_.end()) return std::nullopt;
            return it->second;
        };
        auto cell = [](std::optional<double> v, const char* fmt) {
            char buf[32];
            if (!v) return std::string("-");
            std::snprintf(buf, sizeof buf, fmt, *v);
            return std::string(buf);
        };
        const std::string mt = std::to_string(thread_count()) + "t";
        std::printf("\nSummary (Mrays/s: 1t = one thread's CPU time, %s = per %u dedicated cores; "
                    "medians when repeated)%s\n",
                    mt.c_str(), thread_count(),
                    bench::embree_available() ? "" : "\n  Embree rows are missing: built without Embree");
        std::printf("%-12s %-11s %-4s %9s %9s %9s %9s %7s\n", "mesh", "rays", "thr", "median",
                    "sah", "librt", "embree", "ratio");
        for (const auto& w : workloads)
            for (const char* rays : {"incoherent", "anyhit", "primary"})
                for (const std::string& threads : {std::string("1t"), mt}) {
                    auto mrays = [&](const char* engine) -> std::optional<double> {
                        const auto f = find(w->name + "/" + engine + "/" + rays + "/" + threads);
                        if (!f) return std::nullopt;
                        return f->mrays;
                    };
                    const auto librt = mrays("librt"), embree = mrays("embree");
                    if (!librt && !embree) continue;
                    std::optional<double> ratio;
                    if (librt && embree && *embree > 0.0) ratio = *librt / *embree;
                    std::printf("%-12s %-11s %-4s %9s %9s %9s %9s %7s\n", w->name.c_str(), rays,
                                threads.c_str(), cell(mrays("median"), "%.3f").c_str(),
                                cell(mrays("sah"), "%.3f").c_str(), cell(librt, "%.3f").c_str(),
                                cell(embree, "%.3f").c_str(), cell(ratio, "%.2f").c_str());
                }
        std::printf("\n%-12s %10s %10s %7s %11s %11s %7s\n", "mesh", "librt ms", "embree ms",
                    "ratio", "librt B/tri", "embree B/tri", "ratio");
        for (const auto& w : workloads) {
            const auto l = find(w->name + "/librt/build"), e = find(w->name + "/embree/build");
            if (!l && !e) continue;
            std::optional<double> lms, ems, lb, eb, rms, rb;
            if (l) lms = l->ms, lb = l->bytes_per_tri;
            if (e) ems = e->ms, eb = e->bytes_per_tri;
            if (l && e && e->ms > 0.0) rms = l->ms / e->ms;
            if (l && e && e->bytes_per_tri > 0.0) rb = l->bytes_per_tri / e->bytes_per_tri;
            std::printf("%-12s %10s %10s %7s %11s %11s %7s\n", w->name.c_str(), cell(lms, "%.1f").c_str(),
                        cell(ems, "%.1f").c_str(), cell(rms, "%.2f").c_str(), cell(lb, "%.1f").c_str(),
                        cell(eb, "%.1f").c_str(), cell(rb, "%.2f").c_str());
        }
        double load[3] = {0, 0, 0};
        if (getloadavg(load, 3) == 3)
            std::printf("\nload average at the end of the run: %.2f %.2f %.2f\n", load[0], load[1], load[2]);
    }

private:
    std::map<std::string, Figures> rows_;
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
