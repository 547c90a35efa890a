// Issue 40 item 3: librt against Embree on scenes of 100 million triangles (instanced) and
// 10 million unique triangles: build time, memory per triangle, rays per second, and the
// build's scaling from 1 to 2 cores. A timed program rather than Google Benchmark: a build
// takes seconds and the process's peak memory is part of the result.
//
//   librt_scale_bench --scene forest|teapot [options]
//     --engines librt,embree   which engines (default both when built with Embree)
//     --reps N                 paired repetitions of each build and each ray set (3)
//     --rays N                 incoherent rays (1048576); primary rays are 1024 x 1024
//     --no-trace               builds and memory only
//     --scaling                librt's build with 1 thread against 2 (paired), and the SAH
//                              builder alone with 1 and 2 threads; an Amdahl fit for 16
//     --embree-quality Q       default or high (RTC_BUILD_QUALITY_HIGH)
//     --build-threads N        librt's builds take N threads (0: all; for callgrind runs)
//     --dragons N --bunnies N  the forest (110 and 60: 100,022,600 triangles placed)
//     --teapot N               the teapot's triangles (10,000,000)
//     --write-gltf DIR         write DIR/forest.gltf and .bin (the same forest) and stop
//   librt_scale_bench --check  writes a small forest of procedural prototypes as glTF to a
//                              temporary directory, loads it with librt's loader and checks
//                              the instances, their prototypes' triangle counts and
//                              matrices against the layout (a ctest; needs no data)
//
// Paired timing, as librt_bench: builds alternate which engine goes first; rays go in chunks
// of 32,768, each chunk through both engines (alternating order) on one thread, each engine
// timed by its thread's CPU clock. Ratios are librt / Embree per repetition; medians and
// ranges are printed. The last line is the process's peak RSS (getrusage): run one engine
// at a time for each engine's own peak.
//
// About 520 lines, over the usual 400: the options, the paired timing of builds and rays and
// the scaling fit share the Spread records and the printed layout; the scenes and engines
// live in scale_scene.h, the glTF check in forest_check.cpp.

#include "../../tests/ray_sets.h"
#include "../embree_scene.h"
#include "forest.h"
#include "scale_scene.h"

#include <librt/accel/bvh_builder.h>
#include <librt/accel/triangle_bvh.h>
#include <librt/core/error.h>
#include <librt/geometry/triangle.h>

#include <dlfcn.h>
#include <glm/geometric.hpp>
#include <glm/trigonometric.hpp>
#include <sys/resource.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>
#include <vector>

namespace {

/// Build threads for the scaling runs: 0 = the machine's. librt's builders take
/// std::thread::hardware_concurrency() threads, which libstdc++ asks of glibc's get_nprocs();
/// the definition below (this executable's, so it wins over glibc's for libstdc++ too) lets
/// the benchmark choose 1 or 2 without a knob in the library.
std::atomic<int> g_build_threads{0};

}  // namespace

extern "C" int get_nprocs() {
    if (const int forced = g_build_threads.load(); forced > 0) return forced;
    using Fn = int (*)();
    static const auto real = reinterpret_cast<Fn>(dlsym(RTLD_NEXT, "get_nprocs"));
    return real ? real() : 1;
}

namespace {

using namespace librt;
using bench::EmbreeEngine;
using bench::LibrtEngine;
using bench::SceneData;
namespace fs = std::filesystem;

fs::path data_dir() {
    if (const char* env = std::getenv("LIBRT_DATA_DIR"); env && *env) return env;
    return LIBRT_DEFAULT_DATA_DIR;
}

struct Options {
    std::string scene;
    bool librt = true;
    bool embree = bench::embree_available();
    int reps = 3;
    std::size_t rays = std::size_t(1) << 20;
    bool trace = true;
    bool scaling = false;
    bench::EmbreeQuality quality = bench::EmbreeQuality::Default;
    std::uint32_t dragons = 110, bunnies = 60;
    std::size_t teapot = 10'000'000;
    std::string gltf_dir;
    bool check = false;
};

[[noreturn]] void usage(const std::string& problem) {
    std::cerr
        << "librt_scale_bench: " << problem
        << "\nusage: librt_scale_bench --scene forest|teapot [--engines librt,embree] "
           "[--reps N] [--rays N] [--no-trace] [--scaling] [--build-threads N] [--embree-quality "
           "default|high] [--dragons N] [--bunnies N] [--teapot N] [--write-gltf DIR] | "
           "--check\n";
    std::exit(2);
}

std::uint64_t parse_count(const std::string& flag, const std::string& value) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(value.c_str(), &end, 10);
    if (value.empty() || *end != '\0' || value[0] == '-')
        usage(flag + " = '" + value + "': expected a non-negative integer");
    return v;
}

Options parse(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        auto value = [&]() -> std::string {
            if (i + 1 >= argc) usage(a + ": missing its value");
            return argv[++i];
        };
        if (a == "--scene") {
            o.scene = value();
            if (o.scene != "forest" && o.scene != "teapot")
                usage("--scene = '" + o.scene + "': expected forest or teapot");
        } else if (a == "--engines") {
            const std::string v = value();
            o.librt = v.find("librt") != std::string::npos;
            o.embree = v.find("embree") != std::string::npos;
            if (!o.librt && !o.embree) usage("--engines = '" + v + "': expected librt,embree");
            if (o.embree && !bench::embree_available())
                usage("--engines = '" + v + "': built without Embree");
        } else if (a == "--reps") {
            o.reps = int(std::max<std::uint64_t>(1, parse_count(a, value())));
        } else if (a == "--rays") {
            o.rays = std::max<std::uint64_t>(1, parse_count(a, value()));
        } else if (a == "--no-trace") {
            o.trace = false;
        } else if (a == "--scaling") {
            o.scaling = true;
        } else if (a == "--embree-quality") {
            const std::string v = value();
            if (v != "default" && v != "high")
                usage("--embree-quality = '" + v + "': expected default or high");
            o.quality = v == "high" ? bench::EmbreeQuality::High : bench::EmbreeQuality::Default;
        } else if (a == "--dragons") {
            o.dragons = std::uint32_t(parse_count(a, value()));
        } else if (a == "--bunnies") {
            o.bunnies = std::uint32_t(parse_count(a, value()));
        } else if (a == "--teapot") {
            o.teapot = std::max<std::uint64_t>(1, parse_count(a, value()));
        } else if (a == "--write-gltf") {
            o.gltf_dir = value();
            o.scene = "forest";
        } else if (a == "--build-threads") {
            g_build_threads = int(std::min<std::uint64_t>(1024, parse_count(a, value())));
        } else if (a == "--check") {
            o.check = true;
        } else {
            usage("unknown argument '" + a + "'");
        }
    }
    if (!o.check && o.scene.empty()) usage("--scene is required");
    return o;
}

double wall_seconds() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch())
        .count();
}

double thread_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double process_cpu_seconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

double peak_rss_mib() {
    rusage u{};
    getrusage(RUSAGE_SELF, &u);
    return double(u.ru_maxrss) / 1024.0;  // Linux reports KiB
}

/// Median, min and max of a sample (sorted copy).
struct Spread {
    double median = 0, lo = 0, hi = 0;
};
Spread spread(std::vector<double> v) {
    if (v.empty()) return {};
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    const double median = n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    return {median, v.front(), v.back()};
}

std::size_t mesh_array_bytes(const TriangleMesh& m) {
    return m.positions.size() * sizeof(glm::vec3) + m.triangles.size() * sizeof(glm::uvec3);
}

// ---------------------------------------------------------------------------------------
// Measurements

/// Pinhole rays through a res x res image from forest_camera, vertical fov 40 degrees.
std::vector<Ray> forest_primary_rays(std::size_t instances, int res) {
    const bench::ForestCamera cam = bench::forest_camera(instances);
    const glm::vec3 w = glm::normalize(cam.eye - cam.target);
    const glm::vec3 u = glm::normalize(glm::cross(glm::vec3(0, 1, 0), w));
    const glm::vec3 v = glm::cross(w, u);
    const float half = std::tan(glm::radians(20.0f));
    std::vector<Ray> rays;
    rays.reserve(std::size_t(res) * std::size_t(res));
    for (int i = 0; i < res; ++i)
        for (int j = 0; j < res; ++j) {
            const float x = (2.0f * (float(j) + 0.5f) / float(res) - 1.0f) * half;
            const float y = (1.0f - 2.0f * (float(i) + 0.5f) / float(res)) * half;
            Ray r;
            r.origin = cam.eye;
            r.direction = glm::normalize(x * u + y * v - w);
            rays.push_back(r);
        }
    return rays;
}

enum class Query { Closest, Any };

template <class Engine>
std::size_t trace(const Engine& e, const Ray* rays, std::size_t n, Query q) {
    std::size_t hits = 0;
    for (std::size_t i = 0; i < n; ++i)
        hits += q == Query::Any ? e.occluded(rays[i]) : e.intersect(rays[i]).valid();
    return hits;
}

/// Traces `rays` through both engines (either may be null) in paired chunks, `reps` times;
/// prints each engine's Mrays/s (median) and the ratio's median and range.
void trace_rows(const char* label, const std::vector<Ray>& rays, Query q, int reps,
                const LibrtEngine* a, const EmbreeEngine* b) {
    constexpr std::size_t kChunk = 1u << 15;
    std::vector<double> ra, rb, ratio;
    std::size_t hits_a = 0, hits_b = 0;
    for (int rep = 0; rep < reps; ++rep) {
        double ta = 0, tb = 0;
        hits_a = hits_b = 0;
        for (std::size_t k = 0; k * kChunk < rays.size(); ++k) {
            const Ray* first = rays.data() + k * kChunk;
            const std::size_t n = std::min(kChunk, rays.size() - k * kChunk);
            auto run_a = [&] {
                if (!a) return;
                const double t0 = thread_cpu_seconds();
                hits_a += trace(*a, first, n, q);
                ta += thread_cpu_seconds() - t0;
            };
            auto run_b = [&] {
                if (!b) return;
                const double t0 = thread_cpu_seconds();
                hits_b += trace(*b, first, n, q);
                tb += thread_cpu_seconds() - t0;
            };
            if ((k + std::size_t(rep)) % 2 == 0) {
                run_a();
                run_b();
            } else {
                run_b();
                run_a();
            }
        }
        const double n = double(rays.size()) * 1e-6;
        if (a) ra.push_back(n / ta);
        if (b) rb.push_back(n / tb);
        if (a && b) ratio.push_back((n / ta) / (n / tb));
    }
    const double total = double(rays.size());
    const auto rate = [&](bool has, const std::vector<double>& r, std::size_t hits) {
        char buf[48];
        if (!has) return std::string("        -       -");
        std::snprintf(buf, sizeof buf, " %9.3f %6.2f%%", spread(r).median,
                      100.0 * double(hits) / total);
        return std::string(buf);
    };
    std::printf("%-18s %9zu%s%s", label, rays.size(), rate(a, ra, hits_a).c_str(),
                rate(b, rb, hits_b).c_str());
    if (a && b) {
        const Spread r = spread(ratio);
        std::printf("  %5.2f (%.2f-%.2f)", r.median, r.lo, r.hi);
    }
    std::printf("\n");
    std::fflush(stdout);
}

/// Amdahl's law (Amdahl 1967): speedup on p processors of work whose serial fraction is f.
double amdahl(double f, double p) { return 1.0 / (f + (1.0 - f) / p); }

/// The serial fraction that explains a measured speedup s on p processors (Karp & Flatt
/// 1990): f = (1/s - 1/p) / (1 - 1/p).
double karp_flatt(double s, double p) { return (1.0 / s - 1.0 / p) / (1.0 - 1.0 / p); }

void print_fit(const char* what, const std::vector<double>& t1, const std::vector<double>& t2,
               const std::vector<double>& speedups, const std::vector<double>& parallelism) {
    const Spread s = spread(speedups);
    const double f = karp_flatt(s.median, 2.0);
    std::printf("%-34s 1 thread %8.1f ms  2 threads %8.1f ms  speedup %.2f (%.2f-%.2f)", what,
                1e3 * spread(t1).median, 1e3 * spread(t2).median, s.median, s.lo, s.hi);
    if (!parallelism.empty()) std::printf("  CPU/wall at 2: %.2f", spread(parallelism).median);
    if (s.median <= 1.0) {
        // No speed-up (a busy machine shares its cores between sessions, not threads): a
        // serial fraction of 1 or more says nothing about the code.
        std::printf("\n%-34s no speed-up measured: no Amdahl fit (see docs/benchmarks.md)\n", "");
        return;
    }
    std::printf(
        "\n%-34s serial fraction (Karp-Flatt) %.3f -> Amdahl: %.2fx on 4, %.2fx on 8, "
        "%.2fx on 16 threads\n",
        "", f, amdahl(f, 4), amdahl(f, 8), amdahl(f, 16));
}

/// librt's build with 1 thread against 2 (g_build_threads, see get_nprocs), alternating
/// which goes first; then the SAH builder alone with SahConfig::thread_count 1 and 2 over
/// the first prototype's triangle boxes.
void scaling(const SceneData& s, int reps) {
    std::vector<double> t1, t2, speedup, parallel;
    for (int rep = 0; rep < reps; ++rep) {
        double one = 0, two = 0;
        auto run_one = [&] {
            g_build_threads = 1;
            one = LibrtEngine::build(s).second;
            g_build_threads = 0;
        };
        auto run_two = [&] {
            g_build_threads = 2;
            const double c0 = process_cpu_seconds();
            two = LibrtEngine::build(s).second;
            parallel.push_back((process_cpu_seconds() - c0) / two);
            g_build_threads = 0;
        };
        if (rep % 2 == 0) {
            run_one();
            run_two();
        } else {
            run_two();
            run_one();
        }
        t1.push_back(one);
        t2.push_back(two);
        speedup.push_back(one / two);
    }
    std::printf("\nBuild scaling (librt, %s, %d paired repetitions)\n", s.name.c_str(), reps);
    print_fit(s.placements.empty() ? "TriangleBvh build" : "TopLevel build (prototypes + top)", t1,
              t2, speedup, parallel);

    // The SAH builder alone, threads chosen through its config.
    const TriangleMesh& m = s.prototypes[0];
    std::vector<BBox> boxes(m.triangle_count());
    std::vector<glm::vec3> centers(m.triangle_count());
    for (std::size_t i = 0; i < boxes.size(); ++i) {
        boxes[i] = bounds(m.triangle(i));
        centers[i] = boxes[i].center();
    }
    std::vector<double> b1, b2, bs;
    for (int rep = 0; rep < reps; ++rep) {
        double x1 = 0, x2 = 0;
        auto run = [&](std::uint32_t threads) {
            SahConfig config = triangle_sah_config();
            config.thread_count = threads;
            const double start = wall_seconds();
            const Bvh bvh = build_sah_bvh(boxes, centers, config);
            const double t = wall_seconds() - start;
            if (bvh.nodes.empty()) throw Error("empty SAH tree");
            return t;
        };
        if (rep % 2 == 0) {
            x1 = run(1);
            x2 = run(2);
        } else {
            x2 = run(2);
            x1 = run(1);
        }
        b1.push_back(x1);
        b2.push_back(x2);
        bs.push_back(x1 / x2);
    }
    print_fit("build_sah_bvh, thread_count 1 vs 2", b1, b2, bs, {});
}

int run_scene(const Options& o) {
    const double rss0 = peak_rss_mib();
    const SceneData s = o.scene == "forest" ? bench::make_forest(data_dir(), o.dragons, o.bunnies)
                                            : bench::make_teapot(o.teapot);
    if (!o.gltf_dir.empty()) {
        fs::create_directories(o.gltf_dir);
        bench::write_forest_gltf(o.gltf_dir, "forest", s.prototypes, s.placements);
        std::printf("wrote %s/forest.gltf: %zu instances, %zu triangles stored, %zu placed\n",
                    o.gltf_dir.c_str(), s.placements.size(), s.unique, s.placed);
        return 0;
    }
    std::size_t mesh_bytes = 0;
    for (const TriangleMesh& m : s.prototypes) mesh_bytes += mesh_array_bytes(m);
    std::printf(
        "scene %s: %zu unique triangles, %zu placed (%zu instances); mesh arrays %.1f "
        "MB; peak RSS after loading %.0f MiB (at start %.0f)\n",
        s.name.c_str(), s.unique, s.placed, s.placements.size(), 1e-6 * double(mesh_bytes),
        peak_rss_mib(), rss0);

    // Builds, paired; the last of each is kept for the rays.
    std::unique_ptr<LibrtEngine> librt;
    std::unique_ptr<EmbreeEngine> embree;
    std::vector<double> ta, tb, ratio;
    for (int rep = 0; rep < o.reps; ++rep) {
        auto run_a = [&] {
            if (!o.librt) return;
            librt.reset();
            auto [e, t] = LibrtEngine::build(s);
            librt = std::move(e);
            ta.push_back(t);
        };
        auto run_b = [&] {
            if (!o.embree) return;
            embree.reset();
            embree = std::make_unique<EmbreeEngine>(s, o.quality);
            tb.push_back(embree->build_seconds());
        };
        if (rep % 2 == 0) {
            run_a();
            run_b();
        } else {
            run_b();
            run_a();
        }
        if (o.librt && o.embree) ratio.push_back(ta.back() / tb.back());
    }
    const char* quality = o.quality == bench::EmbreeQuality::High ? "high" : "default";
    std::printf("\nbuild (wall, %d paired reps, medians):", o.reps);
    if (o.librt) std::printf("  librt %.1f ms", 1e3 * spread(ta).median);
    if (o.embree) std::printf("  embree(%s) %.1f ms", quality, 1e3 * spread(tb).median);
    if (!ratio.empty())
        std::printf("  ratio %.2f (%.2f-%.2f)", spread(ratio).median, spread(ratio).lo,
                    spread(ratio).hi);
    std::printf("\n");
    const double mesh = double(mesh_bytes);
    const auto memory = [&](const char* engine, double accel) {
        std::printf(
            "memory %-7s accel %8.1f MB: %6.1f B per unique triangle, %7.3f per placed; "
            "with the mesh arrays %6.1f B per unique triangle, %7.3f per placed\n",
            engine, 1e-6 * accel, accel / double(s.unique), accel / double(s.placed),
            (accel + mesh) / double(s.unique), (accel + mesh) / double(s.placed));
    };
    if (librt) memory("librt", double(librt->accel_bytes()));
    if (embree) memory("embree", double(embree->accel_bytes()));
    std::printf("peak RSS after the builds: %.0f MiB\n", peak_rss_mib());

    if (o.trace) {
        const BBox box = [&] {
            BBox b;
            if (s.placements.empty()) return s.prototypes[0].bounds();
            // The world box: every placed prototype's box corners.
            for (const bench::ForestPlacement& p : s.placements) {
                const BBox local = s.prototypes[p.prototype].bounds();
                for (int c = 0; c < 8; ++c) {
                    const glm::vec3 q((c & 1) ? local.hi.x : local.lo.x,
                                      (c & 2) ? local.hi.y : local.lo.y,
                                      (c & 4) ? local.hi.z : local.lo.z);
                    b.extend(glm::vec3(p.object_to_world * glm::vec4(q, 1.0f)));
                }
            }
            return b;
        }();
        const std::vector<Ray> incoherent = librt::testing::incoherent_rays(box, o.rays, 42);
        // Primary rays: librt_bench's camera framing the mesh; for the forest the glTF's
        // camera looking down on it (librt_bench's would see its edge only).
        const std::vector<Ray> primary = s.placements.empty()
                                             ? librt::testing::primary_rays(box, 1024, 1024, 40.0f)
                                             : forest_primary_rays(s.placements.size(), 1024);
        std::printf(
            "\nrays, one thread (%d paired reps): Mrays/s per engine (median), hits, "
            "ratio librt/embree median (range)\n",
            o.reps);
        std::printf("%-18s %9s %9s %7s %9s %7s  %s\n", "rays", "count", "librt", "hit", "embree",
                    "hit", "ratio");
        trace_rows("incoherent", incoherent, Query::Closest, o.reps, librt.get(), embree.get());
        trace_rows("incoherent anyhit", incoherent, Query::Any, o.reps, librt.get(), embree.get());
        trace_rows("primary", primary, Query::Closest, o.reps, librt.get(), embree.get());
    }
    if (o.scaling) {
        librt.reset();
        embree.reset();
        scaling(s, o.reps);
    }
    double load[3] = {0, 0, 0};
    if (getloadavg(load, 3) == 3) std::printf("\nload average at the end: %.2f\n", load[0]);
    std::printf("peak RSS: %.0f MiB\n", peak_rss_mib());
    return 0;
}

}  // namespace

int main(int argc, char** argv) {
    try {
        const Options o = parse(argc, argv);
        return o.check ? bench::check_forest_gltf() : run_scene(o);
    } catch (const std::exception& e) {
        std::cerr << "librt_scale_bench: " << e.what() << "\n";
        return 1;
    }
}
