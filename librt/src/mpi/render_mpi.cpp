// render_mpi: rank 0 schedules jobs (tiles) and gathers them; every rank renders (rank 0
// on a thread of its own). The protocol, all point-to-point on `comm` (the messages are
// packed and read in mpi_messages.cpp):
//   worker -> 0  kRequest  int32 job (-1: none yet), then that tile's FilmPixel records row
//                          by row, then its AovPixel records, then (when the integrator
//                          keeps its training passes, or for an adaptive pilot) the
//                          FilmPixel records of the tile at half its samples; "give me
//                          another"
//   worker -> 0  kFail     the error message of an exception on the worker (its last word)
//   worker -> 0  kCancel   the worker's cancel flag stopped it (its last word)
//   worker -> 0  kSplats   after kDone, for an integrator that splats: its splat sums over
//                          the whole image (int64), then its clipped and non-finite counts,
//                          and with kept training passes the same for its first halves;
//                          empty when it rendered no tile (its last word)
//   0 -> worker  kAssign   int32 job to render next: j < tiles, tile j from no samples; with
//                          adaptive sampling, tiles + t: tile t's FilmPixel and AovPixel
//                          records and its pixels' uint32 counts, to continue
//   0 -> worker  kDone     no jobs left: return
//   0 -> worker  kStop     the job failed or was cancelled (payload: why): return or throw
// Every kRequest gets exactly one answer (with adaptive sampling, a request between the
// pilots and the counts waits for it) and every worker ends with exactly one of kFail,
// kCancel, kSplats (splatting), or a kRequest answered by kStop or (not splatting) kDone,
// so rank 0 knows when all have finished and no rank waits for a message that never comes.
// Over 400 lines: rank 0's loop and the worker's are the two sides of one protocol and
// are read together.

#include "mpi/mpi_messages.h"
#include "render/pass_sequence.h"

#include <librt/core/error.h>
#include <librt/mpi/render_mpi.h>
#include <librt/mpi/same_job.h>
#include <librt/render/adaptive_sampling.h>
#include <librt/render/pass_combination.h>
#include <librt/scene/scene.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <exception>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <utility>
#include <vector>

namespace librt {

namespace {

using namespace mpi_detail;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

// How long rank 0's main thread sleeps when no message is waiting. Open MPI's blocking
// receive spins a core, which on a machine whose cores all render would steal one from
// the renderer. A wake-up with its MPI_Iprobe costs ~5 us of CPU (measured here), so a
// 500 us nap costs ~1% of a core and delays an answer by 250 us on average, against tiles
// that take tens of milliseconds to seconds. Alone (one rank) it only watches its thread.
constexpr auto kPollInterval = std::chrono::microseconds(500);
constexpr auto kPollIntervalAlone = std::chrono::milliseconds(5);

// A worker waiting for rank 0's answer. Open MPI's blocking MPI_Probe spins a core for as
// long as the answer takes: the round trip between tiles (under a millisecond), but with
// adaptive sampling also the wait for the last pilot, a tile's time, during which the
// spinning core is taken from the ranks that still render. So: probe without blocking
// for about 200 us (the usual answer comes within rank 0's 500 us nap), then nap 200 us
// between probes.
void wait_for_answer(MPI_Comm comm, MPI_Status& status) {
    const Clock::time_point start = Clock::now();
    for (int flag = 0;;) {
        check(MPI_Iprobe(0, MPI_ANY_TAG, comm, &flag, &status), "MPI_Iprobe");
        if (flag) return;
        if (Clock::now() - start > std::chrono::microseconds(200))
            std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
}

// The settings of a rank's blocks: no progress (render_mpi reports it itself, on rank 0's
// calling thread) and the rank's cancel flag; the jobs say each pixel's samples.
BlockSettings block_settings(const MpiRenderSettings& s, const std::atomic<bool>* cancel) {
    BlockSettings r = s.render.block();
    r.progress = {};
    r.cancel = cancel;
    return r;
}

// What a rank renders for job j (the jobs of run_root), as render() renders the whole
// image (PassSequence): tile j from no samples through the plan's uniform stage, to spp or
// (adaptive sampling) to the pilot, in its two halves when the plan says, copying the
// tile's records into `half` (a film of the same size and placement) between them; or job
// count + t, tile t's rest stage, from the pilot on to each pixel's count (`ends`: one per
// pixel of `film`). With kept training passes, a splatting integrator's splats of the
// first half go to half.splats, of the second to film.splats (see run_root): the splats
// of the image at half its samples, and what completes them.
struct Job {
    const Scene& scene;
    const Camera& camera;
    const Integrator& integrator;
    const Tiling& tiling;
    RenderPlan plan;
    RenderStats render(int job, Film& film, FilmOrigin origin, Film& half,
                       std::span<const std::uint32_t> ends, const BlockSettings& rs) const {
        const Rect r = tiling.rect(job % tiling.count);
        RenderStats stats;
        PassRunner runner;
        const bool rest = job >= tiling.count;
        // The rest stage is one pass (no pass size), to the counts themselves: `ends`.
        runner.pass = [&](std::uint32_t first, std::uint32_t count, const std::uint32_t*) {
            const RenderBlock block{r.x0, r.y0, r.x1, r.y1, first, count};
            if (rest) {
                const RenderStats st = render_block_to_counts(scene, camera, integrator, film,
                                                              origin, block, ends, rs);
                stats.samples += st.samples;
                stats.nonfinite_samples += st.nonfinite_samples;
                stats.cancelled = st.cancelled;
                return !st.cancelled;
            }
            const bool split_splats = plan.keep && first < plan.half_level();
            if (split_splats) std::swap(film.splats, half.splats);
            RenderStats st;
            try {
                st = render_block(scene, camera, integrator, film, origin, block, rs);
            } catch (...) {
                if (split_splats) std::swap(film.splats, half.splats);
                throw;
            }
            if (split_splats) std::swap(film.splats, half.splats);
            stats.samples += st.samples;
            stats.nonfinite_samples += st.nonfinite_samples;
            stats.cancelled = st.cancelled;
            return !st.cancelled;
        };
        runner.reached_half = [&] {
            const auto row = static_cast<std::ptrdiff_t>(r.x1 - r.x0);
            for (int y = r.y0; y < r.y1; ++y) {
                const std::size_t i = film.index(r.x0 - origin.x, y - origin.y);
                std::copy_n(film.pixels.begin() + static_cast<std::ptrdiff_t>(i), row,
                            half.pixels.begin() + static_cast<std::ptrdiff_t>(i));
            }
        };
        if (rest) {
            PassSequence(plan, plan.pilot).run_rest(runner, ends);
        } else {
            PassSequence(plan, 0).run_uniform(runner);
        }
        return stats;
    }
};

// Rank 0: schedules, gathers, and (unless told not to, or alone) renders on a thread.
// The jobs: tiles [0, count), each rendered whole. With adaptive sampling, those render
// the pilot; once every pilot is back, rank 0 computes each pixel's count from the whole
// image (as render() does) and hands out jobs [count, 2 count), each a tile's pilot
// records and counts, to be continued and sent back. Requests that arrive in between wait.
Film run_root(MPI_Comm comm, int size, const Scene& scene, const Camera& camera,
              Integrator& integrator, const MpiRenderSettings& s, MpiRenderStats& stats,
              Image* image) {
    const Clock::time_point start = Clock::now();
    std::string failure;  // "rank R failed: ..." once something failed
    bool stopping = false;
    Film film;
    Film half;  // the film at half its samples (radiance only): kept passes' or the pilot's
    PassCombination kept_passes;
    RenderPlan plan;
    bool splatting = false;
    const std::uint32_t spp = static_cast<std::uint32_t>(s.render.samples_per_pixel);
    // The workers' splats (kSplats): of their second halves with `kept`, else all; and of
    // their first halves. Rank 0's own thread splats into film.splats and half.splats.
    std::optional<SplatFilm> worker_splats, worker_first_splats;
    Tiling tiling(camera.width(), camera.height(), std::max(1, s.tile_size));
    try {
        validate(s);
        plan = plan_of(s.render);
        film = Film(camera.width(), camera.height(), s.aovs);
        integrator.preprocess(scene);
        // Known after preprocess(); the same answer on every rank, so every rank agrees on
        // the records a tile carries.
        plan.keep = keeps_training_passes(plan, integrator);
        splatting = integrator.splats();
        if (plan.in_halves()) half = Film(camera.width(), camera.height());
        // Every rank learns the same guide (training is deterministic), so the tiles
        // merge into the one-process image; rank 0 keeps the passes as render() does.
        train(scene, camera, integrator, s.render, plan.keep ? &kept_passes : nullptr);
    } catch (...) {
        failure = "rank 0 failed: " + message_of(std::current_exception());
        stopping = true;
    }
    const std::uint32_t pilot = plan.pilot;
    const bool kept = plan.keep;
    const int count = tiling.count;
    const int jobs = pilot > 0 ? 2 * count : count;
    const Job job_of{scene, camera, integrator, tiling, plan};
    stats.tiles = jobs;
    stats.tiles_per_rank.assign(static_cast<std::size_t>(size), 0);

    std::atomic<int> next_tile{0};      // jobs [0, count)
    std::atomic<int> next_rest{0};      // adaptive: jobs count + [0, count)
    std::vector<std::uint32_t> counts;  // adaptive: each pixel's count, once counts_ready
    std::atomic<bool> counts_ready{false};
    std::atomic<bool> local_cancel{false};
    std::atomic<bool> local_done{true};
    std::atomic<int> local_tiles{0};
    std::atomic<int> local_pilots{0};  // of local_tiles, jobs below count (adaptive)
    std::exception_ptr local_error;
    std::thread local;
    if (!stopping && (s.root_renders || size == 1)) {
        local_done = false;
        local = std::thread([&] {
            try {
                const BlockSettings rs = block_settings(s, &local_cancel);
                bool cancelled = false;
                for (int t = next_tile.fetch_add(1); t < count && !local_cancel.load();
                     t = next_tile.fetch_add(1)) {
                    const RenderStats st = job_of.render(t, film, {}, half, {}, rs);
                    stats.samples += st.samples;
                    stats.nonfinite_samples += st.nonfinite_samples;
                    if ((cancelled = st.cancelled)) break;
                    local_tiles.fetch_add(1);
                    local_pilots.fetch_add(1);
                }
                if (pilot > 0 && !cancelled) {
                    // The counts need every pilot, the workers' too: rank 0's main thread
                    // computes them. Polled, as the main thread polls its messages.
                    while (!counts_ready.load() && !local_cancel.load())
                        std::this_thread::sleep_for(kPollIntervalAlone);
                    for (int t = next_rest.fetch_add(1); t < count && !local_cancel.load();
                         t = next_rest.fetch_add(1)) {
                        const RenderStats st = job_of.render(count + t, film, {}, half, counts, rs);
                        stats.samples += st.samples;
                        stats.nonfinite_samples += st.nonfinite_samples;
                        if (st.cancelled) break;
                        local_tiles.fetch_add(1);
                    }
                }
            } catch (...) {
                local_error = std::current_exception();
            }
            local_done = true;
        });
    }

    int active = size - 1;     // workers that have not had their last word
    std::vector<int> waiting;  // adaptive: workers whose request waits for the counts
    const auto stop = [&](std::string why) {
        if (!stopping) failure = std::move(why);
        stopping = true;
        local_cancel = true;
        for (const int w : waiting) {
            send_text(failure, w, kStop, comm);
            --active;
        }
        waiting.clear();
    };
    // Answers a worker's request: the next job, a wait for the counts, kDone or kStop.
    const auto answer = [&](int source) {
        if (stopping) {
            send_text(failure, source, kStop, comm);
            --active;
            return;
        }
        int job = next_tile.fetch_add(1);
        if (job >= count && pilot > 0) {
            if (!counts_ready.load()) {
                waiting.push_back(source);
                return;
            }
            job = count + next_rest.fetch_add(1);
        }
        if (job < jobs) {
            const std::vector<std::byte> message = pack_assignment(job, tiling, film, counts);
            send_bytes(message.data(), message.size(), source, kAssign, comm);
            ++stats.tiles_per_rank[static_cast<std::size_t>(source)];
        } else {
            send_bytes(nullptr, 0, source, kDone, comm);
            if (!splatting) --active;  // else its kSplats is its last word
        }
    };

    int gathered = 0;
    int gathered_pilots = 0;
    double last_report = -1.0;
    // Checked at the top of every round, not only when no message waits: a stream of
    // messages must not delay a cancel, nor let the render finish past one.
    const auto check_cancel = [&] {
        if (s.render.cancel != nullptr && s.render.cancel->load() && !stopping) {
            stats.cancelled = true;
            stop("cancelled on rank 0");
        }
    };
    while (active > 0 || !local_done.load()) {
        check_cancel();
        // Every pilot back (the local thread's too): the counts, from the whole image.
        if (pilot > 0 && !stopping && !counts_ready.load() &&
            gathered_pilots + local_pilots.load() == count) {
            try {
                counts = plan.counts(half, film);  // the sequence's step between its stages
                counts_ready = true;
                for (const int w : std::exchange(waiting, {})) answer(w);
                // The pilot is a stage's end: reported as it happens (the rest already out
                // to the waiting ranks), so a caller may act on it, as on a pass's end.
                if (s.render.progress) {
                    s.render.progress(
                        {double(pilot) / double(spp), seconds_since(start), 0, pilot});
                    check_cancel();
                }
            } catch (...) {
                stop("rank 0 failed: " + message_of(std::current_exception()));
            }
        }
        int flag = 0;
        MPI_Status status;
        check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, comm, &flag, &status), "MPI_Iprobe");
        if (flag) {
            const int source = status.MPI_SOURCE;
            const Clock::time_point t0 = Clock::now();
            if (status.MPI_TAG == kSplats) {
                const std::vector<std::int64_t> sums = receive_int64s(status, comm);
                try {
                    if (!stopping)
                        unpack_splats(sums, kept, camera, worker_splats, worker_first_splats,
                                      source);
                } catch (...) {
                    stop(message_of(std::current_exception()));
                }
                stats.gather_bytes += sums.size() * sizeof(std::int64_t);
                stats.gather_seconds += seconds_since(t0);
                --active;
                continue;
            }
            const std::vector<std::byte> message = receive(status, comm);
            if (status.MPI_TAG == kRequest) {
                try {
                    const int job = stopping ? -1
                                             : unpack(film, half, kept || pilot > 0, tiling, jobs,
                                                      message, source);
                    if (job >= 0) {
                        ++gathered;
                        if (job < count) ++gathered_pilots;
                    }
                } catch (...) {
                    stop(message_of(std::current_exception()));
                }
                stats.gather_bytes += message.size();
                stats.gather_seconds += seconds_since(t0);
                answer(source);
            } else if (status.MPI_TAG == kFail) {
                stop("rank " + std::to_string(source) + " failed: " + text_of(message));
                --active;
            } else if (status.MPI_TAG == kCancel) {
                stats.cancelled = true;
                stop("cancelled on rank " + std::to_string(source));
                --active;
            } else {
                stop("render_mpi: unexpected message tag " + std::to_string(status.MPI_TAG) +
                     " from rank " + std::to_string(source));
            }
            continue;  // drain every waiting message before napping
        }
        if (local_done.load() && local_error && !stopping) {
            stop("rank 0 failed: " + message_of(local_error));
        }
        const double now = seconds_since(start);
        if (s.render.progress && now - last_report >= 0.1) {
            last_report = now;
            // Each job weighs its share of the samples (adaptive: the pilot's, the rest's).
            const double pilots = gathered_pilots + local_pilots.load();
            const double rests = gathered + local_tiles.load() - pilots;
            const double share = pilot > 0 ? double(pilot) / double(spp) : 1.0;
            s.render.progress(
                {count > 0 ? (pilots * share + rests * (1.0 - share)) / count : 1.0, now, 0, 0});
        }
        std::this_thread::sleep_for(size > 1 ? kPollInterval : kPollIntervalAlone);
    }
    if (local.joinable()) local.join();
    if (local_error && failure.empty()) failure = "rank 0 failed: " + message_of(local_error);
    // Every rank's splats into the film's (integer sums: exact in any order); with kept
    // passes, the first halves' into half.splats and, with the rest, into film.splats.
    try {
        add_splats(film.splats, worker_splats);
        add_splats(half.splats, worker_first_splats);
        if (kept) add_splats(film.splats, half.splats);
    } catch (...) {
        if (failure.empty()) failure = "rank 0 failed: " + message_of(std::current_exception());
    }
    stats.tiles_rendered = local_tiles.load();
    stats.tiles_per_rank[0] = stats.tiles_rendered;
    stats.seconds = seconds_since(start);
    if (stats.cancelled) {
        if (image != nullptr) *image = resolve(film);
        return film;
    }
    if (!failure.empty()) throw Error(failure);
    if (image != nullptr) *image = kept ? kept_passes.combined(half, film) : resolve(film);
    if (s.render.progress) s.render.progress({1.0, stats.seconds, 1, spp});
    return film;
}

// What every rank must agree on before the protocol starts: what shapes its messages (the
// tiling, the records a tile carries, whether splats follow) and the samples. A rank that
// disagreed would wait for messages that never come (a worker whose integrator splats
// sent splats rank 0 never received, both waiting for ever), or its tiles would carry
// another image. Not the integrator's class: a rank may wrap it (rt_mpi_render's failing
// rank does), and its settings are the caller's to compare. Not settings that only rank 0
// or a rank's own threads use (root_renders, threads, the threads' tile_size, progress,
// cancel).
std::vector<JobItem> protocol_items(const Camera& camera, const Integrator& integrator,
                                    const MpiRenderSettings& s) {
    const AdaptiveSampling& a = s.render.adaptive;
    char max_factor[32];  // every digit: two factors that differ must show it
    std::snprintf(max_factor, sizeof max_factor, "%.17g", a.max_factor);
    return {
        {"image size", std::to_string(camera.width()) + "x" + std::to_string(camera.height())},
        {"tile_size", std::to_string(s.tile_size)},
        {"samples_per_pixel", std::to_string(s.render.samples_per_pixel)},
        {"seed", std::to_string(s.render.seed)},
        {"sampler", s.render.sampler == SamplerKind::Sobol ? "sobol" : "independent"},
        {"adaptive", a.enabled ? "pilot " + std::to_string(a.pilot_samples) + ", radius " +
                                     std::to_string(a.radius) + ", max_factor " + max_factor
                               : "off"},
        {"aovs", s.aovs ? "on" : "off"},
        {"integrator splats", integrator.splats() ? "yes" : "no"},
    };
}

// Any other rank: asks rank 0 for jobs until told there are none left.
Film run_worker(MPI_Comm comm, const Scene& scene, const Camera& camera, Integrator& integrator,
                const MpiRenderSettings& s, MpiRenderStats& stats) {
    const Clock::time_point start = Clock::now();
    const Tiling tiling(camera.width(), camera.height(), std::max(1, s.tile_size));
    // The finished tile the next request carries, on a film of the tile's size only: a
    // worker never holds the whole frame (32 x 32 x 96 bytes with AOVs, not 796 MB at 4K).
    Film film;
    Film half;  // the tile at half its samples: kept training passes' or the pilot's
    std::vector<std::uint32_t> ends;  // a continued tile's counts
    int job = -1;
    try {
        validate(s);
        RenderPlan plan = plan_of(s.render);
        const std::uint32_t pilot = plan.pilot;
        stats.tiles = pilot > 0 ? 2 * tiling.count : tiling.count;
        integrator.preprocess(scene);
        const BlockSettings rs = block_settings(s, s.render.cancel);
        // Not kept here (rank 0 keeps them; no whole-image sums on a worker): a pass
        // rendered in halves teaches PathTracer the same guide, as its records are integer
        // sums that no order or split changes.
        train(scene, camera, integrator, s.render);
        plan.keep = keeps_training_passes(plan, integrator);
        const bool kept = plan.keep;
        const bool splatting = integrator.splats();
        const Job job_of{scene, camera, integrator, tiling, plan};
        // A splatting integrator's splats over all this worker's tiles (of the first halves
        // in `first_splats` with `kept`): whole-image films, sent once at the end.
        std::optional<SplatFilm> splats, first_splats;
        while (true) {
            const Clock::time_point t0 = Clock::now();
            const bool with_half = (kept || pilot > 0) && job < tiling.count;
            const std::vector<std::byte> request = pack(film, half, with_half, job);
            send_bytes(request.data(), request.size(), 0, kRequest, comm);
            stats.gather_bytes += request.size();
            MPI_Status status;
            wait_for_answer(comm, status);
            const std::vector<std::byte> answer = receive(status, comm);
            stats.gather_seconds += seconds_since(t0);
            if (status.MPI_TAG == kDone) {
                if (splatting) {
                    const std::vector<std::int64_t> sums = pack_splats(splats, first_splats, kept);
                    send_int64s(sums, 0, kSplats, comm);
                    stats.gather_bytes += sums.size() * sizeof(std::int64_t);
                }
                break;
            }
            if (status.MPI_TAG == kStop) {
                const std::string why = text_of(answer);
                if (why.rfind("cancelled", 0) == 0) {
                    stats.cancelled = true;
                    break;
                }
                stats.seconds = seconds_since(start);
                throw Error("stopped by rank 0: " + why);
            }
            if (status.MPI_TAG != kAssign) {
                throw Error("render_mpi: unexpected message (tag " +
                            std::to_string(status.MPI_TAG) + ") from rank 0");
            }
            job = unpack_assignment(answer, tiling, s.aovs, film, ends);
            const Rect r = tiling.rect(job % tiling.count);
            film.splats = std::exchange(splats, std::nullopt);
            if ((kept || pilot > 0) && job < tiling.count) half = Film(r.x1 - r.x0, r.y1 - r.y0);
            if (kept) half.splats = std::exchange(first_splats, std::nullopt);
            const RenderStats st = job_of.render(job, film, {r.x0, r.y0}, half, ends, rs);
            splats = std::exchange(film.splats, std::nullopt);
            if (kept) first_splats = std::exchange(half.splats, std::nullopt);
            stats.samples += st.samples;
            stats.nonfinite_samples += st.nonfinite_samples;
            if (st.cancelled) {
                stats.cancelled = true;
                send_bytes(nullptr, 0, 0, kCancel, comm);
                break;
            }
            ++stats.tiles_rendered;
        }
    } catch (const Error& e) {
        // Our own "stopped by rank 0" needs no report: rank 0 knows.
        if (std::string(e.what()).rfind("stopped by rank 0: ", 0) != 0)
            send_text(e.what(), 0, kFail, comm);
        throw;
    } catch (const std::exception& e) {
        send_text(e.what(), 0, kFail, comm);
        throw;
    }
    stats.seconds = seconds_since(start);
    return {};
}

}  // namespace

void validate(const MpiRenderSettings& s) {
    if (s.tile_size < 1 || s.tile_size > 1024) {
        throw Error("tile_size = " + std::to_string(s.tile_size) + ": must be in [1, 1024]");
    }
    validate(s.render);
    if (!s.render.region.whole())
        throw Error("render.region: render_mpi renders the whole image (its tiles say the pixels)");
}

Film render_mpi(MPI_Comm comm, const Scene& scene, const Camera& camera, Integrator& integrator,
                const MpiRenderSettings& settings, MpiRenderStats* stats, Image* image) {
    int rank = 0;
    int size = 1;
    check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
    check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    MpiRenderStats local;
    MpiRenderStats& out = stats != nullptr ? *stats : local;
    out = MpiRenderStats{};
    // The protocol runs on a communicator of this call's own. On `comm` itself, a worker
    // that finished the call and went on to the next (the next frame) would send its first
    // request while rank 0 still waits for its own thread's last tile, and rank 0 would
    // answer it as part of this call; the caller's own messages could be taken too.
    // MPI_Comm_dup is collective, so no rank starts a call before all have reached it.
    MPI_Comm own = MPI_COMM_NULL;
    check(MPI_Comm_dup(comm, &own), "MPI_Comm_dup");
    struct Free {
        MPI_Comm& comm;
        ~Free() { MPI_Comm_free(&comm); }
    } const free_own{own};
    check_same_job(own, protocol_items(camera, integrator, settings));
    return rank == 0 ? run_root(own, size, scene, camera, integrator, settings, out, image)
                     : run_worker(own, scene, camera, integrator, settings, out);
}

void check_all_ranks(MPI_Comm comm, const std::string& local_error) {
    int rank = 0;
    int size = 1;
    check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
    check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    // The lowest failing rank (size when none failed), then its message broadcast from it.
    const int mine = local_error.empty() ? size : rank;
    int first = size;
    check(MPI_Allreduce(&mine, &first, 1, MPI_INT, MPI_MIN, comm), "MPI_Allreduce");
    if (first == size) return;
    int length = rank == first ? static_cast<int>(local_error.size()) : 0;
    check(MPI_Bcast(&length, 1, MPI_INT, first, comm), "MPI_Bcast");
    std::string text =
        rank == first ? local_error : std::string(static_cast<std::size_t>(length), ' ');
    check(MPI_Bcast(text.data(), length, MPI_CHAR, first, comm), "MPI_Bcast");
    throw Error("rank " + std::to_string(first) + ": " + text);
}

}  // namespace librt
