// render_mpi: rank 0 schedules tiles and gathers them; every rank renders (rank 0 on a
// thread of its own). The protocol, all point-to-point on `comm`:
//   worker -> 0  kRequest  int32 tile index (-1: none yet), then that tile's FilmPixel
//                          records row by row, then its AovPixel records, then (when the
//                          integrator keeps its training passes) the FilmPixel records of
//                          the tile at half its samples; "give me another"
//   worker -> 0  kFail     the error message of an exception on the worker (its last word)
//   worker -> 0  kCancel   the worker's cancel flag stopped it (its last word)
//   worker -> 0  kSplats   after kDone, for an integrator that splats: its splat sums over
//                          the whole image (int64), then its clipped and non-finite counts,
//                          and with kept training passes the same for its first halves;
//                          empty when it rendered no tile (its last word)
//   0 -> worker  kAssign   int32 tile index to render next
//   0 -> worker  kDone     no tiles left: return
//   0 -> worker  kStop     the job failed or was cancelled (payload: why): return or throw
// Every kRequest gets exactly one answer and every worker ends with exactly one of kFail,
// kCancel, kSplats (splatting), or a kRequest answered by kStop or (not splatting) kDone,
// so rank 0 knows when all have finished and no rank waits for a message that never comes. A little
// over 400 lines: both sides of the protocol share its private message helpers, so they stay in one
// file.

#include <librt/core/error.h>
#include <librt/mpi/render_mpi.h>
#include <librt/render/camera_importance.h>
#include <librt/render/pass_combination.h>
#include <librt/render/scene.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstddef>
#include <cstring>
#include <exception>
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

namespace librt {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) {
    return std::chrono::duration<double>(Clock::now() - start).count();
}

enum Tag : int {
    kRequest = 1,
    kFail = 2,
    kCancel = 3,
    kAssign = 4,
    kDone = 5,
    kStop = 6,
    kSplats = 7
};

// How long rank 0's main thread sleeps when no message is waiting. Open MPI's blocking
// receive spins a core, which on a machine whose cores all render would steal one from
// the renderer. A wake-up with its MPI_Iprobe costs ~5 us of CPU (measured here), so a
// 500 us nap costs ~1% of a core and delays an answer by 250 us on average, against tiles
// that take tens of milliseconds to seconds. Alone (one rank) it only watches its thread.
constexpr auto k_poll_interval = std::chrono::microseconds(500);
constexpr auto k_poll_interval_alone = std::chrono::milliseconds(5);

static_assert(std::is_trivially_copyable_v<FilmPixel> && std::is_trivially_copyable_v<AovPixel>,
              "tile records travel as raw bytes");

void check(int rc, const char* call) {
    if (rc != MPI_SUCCESS) {
        char text[MPI_MAX_ERROR_STRING];
        int length = 0;
        MPI_Error_string(rc, text, &length);
        throw Error(std::string("render_mpi: ") + call + " failed: " + std::string(text, length));
    }
}

struct Rect {
    int x0, y0, x1, y1;  // pixels [x0, x1) x [y0, y1)
    [[nodiscard]] std::size_t pixels() const {
        return static_cast<std::size_t>(x1 - x0) * static_cast<std::size_t>(y1 - y0);
    }
};

struct Tiling {
    int width, height, side, columns, count;
    Tiling(int w, int h, int s)
        : width(w),
          height(h),
          side(s),
          columns((w + s - 1) / s),
          count(columns * ((h + s - 1) / s)) {}
    [[nodiscard]] Rect rect(int index) const {
        const int x0 = (index % columns) * side;
        const int y0 = (index / columns) * side;
        return {x0, y0, std::min(x0 + side, width), std::min(y0 + side, height)};
    }
};

// Bytes per pixel of a tile's records: its FilmPixel, its AovPixel with AOVs, and its
// FilmPixel at half the samples when training passes are kept (`halves`).
std::size_t record_bytes(const Film& film, bool halves) {
    return sizeof(FilmPixel) + (film.has_aovs() ? sizeof(AovPixel) : 0) +
           (halves ? sizeof(FilmPixel) : 0);
}

// A kRequest message: the tile index, then the tile's records (`tile` is a film of the
// tile's size, so its records are the tile's rows in order), then its AOV records, then
// with `halves` the records of `half` (the tile at half its samples).
std::vector<std::byte> pack(const Film& tile, const Film& half, bool halves, int index) {
    std::vector<std::byte> out(sizeof(std::int32_t));
    const auto index32 = static_cast<std::int32_t>(index);
    std::memcpy(out.data(), &index32, sizeof index32);
    if (index < 0) return out;
    const std::size_t pixels = tile.pixels.size();
    out.resize(out.size() + pixels * record_bytes(tile, halves));
    std::byte* at = out.data() + sizeof(std::int32_t);
    std::memcpy(at, tile.pixels.data(), pixels * sizeof(FilmPixel));
    at += pixels * sizeof(FilmPixel);
    if (tile.has_aovs()) {
        std::memcpy(at, tile.aovs.data(), pixels * sizeof(AovPixel));
        at += pixels * sizeof(AovPixel);
    }
    if (halves) std::memcpy(at, half.pixels.data(), pixels * sizeof(FilmPixel));
    return out;
}

// Copies a kRequest's records into `film` (and with `halves`, the half-sample records
// into `half`); returns the tile index (-1 for none).
int unpack(Film& film, Film& half, bool halves, const Tiling& tiling,
           const std::vector<std::byte>& message, int source) {
    std::int32_t index = -1;
    if (message.size() < sizeof index)
        throw Error("render_mpi: short message from rank " + std::to_string(source));
    std::memcpy(&index, message.data(), sizeof index);
    if (index < 0) return -1;
    const Rect r = tiling.rect(index);
    if (index >= tiling.count ||
        message.size() != sizeof index + r.pixels() * record_bytes(film, halves)) {
        throw Error("render_mpi: rank " + std::to_string(source) + " sent tile " +
                    std::to_string(index) + " in a message of " + std::to_string(message.size()) +
                    " bytes (mismatched settings?)");
    }
    const std::byte* at = message.data() + sizeof index;
    const auto row = static_cast<std::size_t>(r.x1 - r.x0);
    for (int y = r.y0; y < r.y1; ++y) {
        std::memcpy(&film.pixels[film.index(r.x0, y)], at, row * sizeof(FilmPixel));
        at += row * sizeof(FilmPixel);
    }
    if (film.has_aovs()) {
        for (int y = r.y0; y < r.y1; ++y) {
            std::memcpy(&film.aovs[film.index(r.x0, y)], at, row * sizeof(AovPixel));
            at += row * sizeof(AovPixel);
        }
    }
    if (halves) {
        for (int y = r.y0; y < r.y1; ++y) {
            std::memcpy(&half.pixels[half.index(r.x0, y)], at, row * sizeof(FilmPixel));
            at += row * sizeof(FilmPixel);
        }
    }
    return index;
}

std::string message_of(const std::exception_ptr& error) {
    try {
        std::rethrow_exception(error);
    } catch (const std::exception& e) {
        return e.what();
    } catch (...) {
        return "unknown exception";
    }
}

void send_bytes(const void* data, std::size_t size, int dest, int tag, MPI_Comm comm) {
    check(MPI_Send(data, static_cast<int>(size), MPI_BYTE, dest, tag, comm), "MPI_Send");
}

void send_text(const std::string& text, int dest, int tag, MPI_Comm comm) {
    send_bytes(text.data(), text.size(), dest, tag, comm);
}

// Receives the message `status` announced (from MPI_Probe / MPI_Iprobe).
std::vector<std::byte> receive(const MPI_Status& status, MPI_Comm comm) {
    int count = 0;
    check(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
    std::vector<std::byte> data(static_cast<std::size_t>(count));
    check(MPI_Recv(data.data(), count, MPI_BYTE, status.MPI_SOURCE, status.MPI_TAG, comm,
                   MPI_STATUS_IGNORE),
          "MPI_Recv");
    return data;
}

// The splat sums of a worker travel as int64 (counts, not bytes: 3 W H sums would pass an
// int count of bytes at 89 M pixels).
void send_int64s(const std::vector<std::int64_t>& data, int dest, int tag, MPI_Comm comm) {
    if (data.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
        throw Error("render_mpi: " + std::to_string(data.size()) + " splat sums in one message");
    check(MPI_Send(data.data(), static_cast<int>(data.size()), MPI_INT64_T, dest, tag, comm),
          "MPI_Send");
}

std::vector<std::int64_t> receive_int64s(const MPI_Status& status, MPI_Comm comm) {
    int count = 0;
    check(MPI_Get_count(&status, MPI_INT64_T, &count), "MPI_Get_count");
    std::vector<std::int64_t> data(static_cast<std::size_t>(count));
    check(MPI_Recv(data.data(), count, MPI_INT64_T, status.MPI_SOURCE, status.MPI_TAG, comm,
                   MPI_STATUS_IGNORE),
          "MPI_Recv");
    return data;
}

// A kSplats message: the sums and counts of `splats` (a worker's second halves with
// `halves`, else everything), then with `halves` those of `first` (its first halves).
// Empty when the worker has none.
std::vector<std::int64_t> pack_splats(const std::optional<SplatFilm>& splats,
                                      const std::optional<SplatFilm>& first, bool halves) {
    std::vector<std::int64_t> out;
    if (!splats) return out;
    if (halves && !first) throw Error("render_mpi: splats of the first halves are missing");
    const auto append = [&](const SplatFilm& f) {
        out.insert(out.end(), f.sums().begin(), f.sums().end());
        out.push_back(static_cast<std::int64_t>(f.clipped()));
        out.push_back(static_cast<std::int64_t>(f.non_finite()));
    };
    append(*splats);
    if (halves) append(*first);
    return out;
}

// Adds a kSplats message to `rest` and (with `halves`) `first`, creating them as the render
// loop creates a film's splats (splat_filter_settings, the default scale).
void unpack_splats(const std::vector<std::int64_t>& message, bool halves, const Camera& camera,
                   std::optional<SplatFilm>& rest, std::optional<SplatFilm>& first, int source) {
    if (message.empty()) return;
    const std::size_t n =
        3 * static_cast<std::size_t>(camera.width()) * static_cast<std::size_t>(camera.height());
    if (message.size() != (halves ? 2 : 1) * (n + 2)) {
        throw Error("render_mpi: rank " + std::to_string(source) + " sent " +
                    std::to_string(message.size()) +
                    " splat sums and counts (mismatched settings?)");
    }
    const auto add = [&](std::optional<SplatFilm>& into, std::size_t at) {
        if (!into) into.emplace(camera.width(), camera.height(), splat_filter_settings(camera));
        into->merge_sums(std::span(message).subspan(at, n),
                         static_cast<std::uint64_t>(message[at + n]),
                         static_cast<std::uint64_t>(message[at + n + 1]));
    };
    add(rest, 0);
    if (halves) add(first, n + 2);
}

// Adds `from` to `into` (SplatFilm::merge), or copies it when `into` has none.
void add_splats(std::optional<SplatFilm>& into, const std::optional<SplatFilm>& from) {
    if (!from) return;
    if (into) {
        into->merge(*from);
    } else {
        into = from;
    }
}

std::string text_of(const std::vector<std::byte>& data) {
    return {reinterpret_cast<const char*>(data.data()), data.size()};
}

RenderSettings block_settings(const MpiRenderSettings& s, const std::atomic<bool>* cancel) {
    RenderSettings r = s.render;
    r.progress = {};  // render_mpi reports progress itself, on rank 0's calling thread
    r.cancel = cancel;
    return r;
}

// Whether tiles are rendered in halves for kept training passes (as render() does): the
// same answer on every rank, so every rank agrees on the records a tile carries. Asked
// after preprocess() (PathTracer builds its guide there).
bool keeps_halves(const Integrator& integrator, const MpiRenderSettings& s) {
    return integrator.keeps_training_samples() && s.render.samples_per_pixel >= 2;
}

// Renders samples [0, spp) of the pixels `r` onto `film` placed at `origin`. With
// `halves`, as two blocks (the same sums as one), copying the rect's records into `half`
// (a film of the same size and placement) between them; a splatting integrator's splats
// of the first block then go to half.splats, of the second to film.splats.
RenderStats render_tile(const Scene& scene, const Camera& camera, const Integrator& integrator,
                        Film& film, FilmOrigin origin, const Rect& r, std::uint32_t spp,
                        bool halves, Film& half, const RenderSettings& rs) {
    if (!halves)
        return render_block(scene, camera, integrator, film, origin,
                            {r.x0, r.y0, r.x1, r.y1, 0, spp}, rs);
    const std::uint32_t a = spp / 2;
    // The first halves' splats go to half.splats, the rest stay in film.splats (see
    // run_root): the splats of the image at half its samples, and what completes them.
    std::swap(film.splats, half.splats);
    RenderStats st;
    try {
        st = render_block(scene, camera, integrator, film, origin, {r.x0, r.y0, r.x1, r.y1, 0, a},
                          rs);
    } catch (...) {
        std::swap(film.splats, half.splats);
        throw;
    }
    std::swap(film.splats, half.splats);
    if (st.cancelled) return st;
    const auto row = static_cast<std::ptrdiff_t>(r.x1 - r.x0);
    for (int y = r.y0; y < r.y1; ++y) {
        const std::size_t i = film.index(r.x0 - origin.x, y - origin.y);
        std::copy_n(film.pixels.begin() + static_cast<std::ptrdiff_t>(i), row,
                    half.pixels.begin() + static_cast<std::ptrdiff_t>(i));
    }
    const RenderStats b = render_block(scene, camera, integrator, film, origin,
                                       {r.x0, r.y0, r.x1, r.y1, a, spp - a}, rs);
    st.samples += b.samples;
    st.nonfinite_samples += b.nonfinite_samples;
    st.cancelled = b.cancelled;
    return st;
}

// Rank 0: schedules, gathers, and (unless told not to, or alone) renders on a thread.
Film run_root(MPI_Comm comm, int size, const Scene& scene, const Camera& camera,
              Integrator& integrator, const MpiRenderSettings& s, MpiRenderStats& stats,
              Image* image) {
    const Clock::time_point start = Clock::now();
    std::string failure;  // "rank R failed: ..." once something failed
    bool stopping = false;
    Film film;
    Film half;  // with kept training passes: the film at half its samples (radiance only)
    PassCombination kept;
    bool halves = false;
    bool splatting = false;
    // The workers' splats (kSplats): of their second halves with `halves`, else all; and of
    // their first halves. Rank 0's own thread splats into film.splats and half.splats.
    std::optional<SplatFilm> worker_splats, worker_first_splats;
    Tiling tiling(camera.width(), camera.height(), std::max(1, s.tile_size));
    try {
        validate(s);
        film = Film(camera.width(), camera.height(), s.aovs);
        integrator.preprocess(scene);
        halves = keeps_halves(integrator, s);  // known after preprocess()
        splatting = integrator.splats();
        if (halves) half = Film(camera.width(), camera.height());
        // Every rank learns the same guide (training is deterministic), so the tiles
        // merge into the one-process image; rank 0 keeps the passes as render() does.
        train(scene, camera, integrator, block_settings(s, s.render.cancel),
              halves ? &kept : nullptr);
    } catch (...) {
        failure = "rank 0 failed: " + message_of(std::current_exception());
        stopping = true;
    }
    stats.tiles = tiling.count;
    stats.tiles_per_rank.assign(static_cast<std::size_t>(size), 0);

    std::atomic<int> next_tile{0};
    std::atomic<bool> local_cancel{false};
    std::atomic<bool> local_done{true};
    std::atomic<int> local_tiles{0};
    std::exception_ptr local_error;
    std::thread local;
    const auto spp = static_cast<std::uint32_t>(s.render.samples_per_pixel);
    if (!stopping && (s.root_renders || size == 1)) {
        local_done = false;
        local = std::thread([&] {
            try {
                const RenderSettings rs = block_settings(s, &local_cancel);
                for (int t = next_tile.fetch_add(1); t < tiling.count && !local_cancel.load();
                     t = next_tile.fetch_add(1)) {
                    const RenderStats st = render_tile(scene, camera, integrator, film, {},
                                                       tiling.rect(t), spp, halves, half, rs);
                    stats.samples += st.samples;
                    stats.nonfinite_samples += st.nonfinite_samples;
                    if (st.cancelled) break;
                    local_tiles.fetch_add(1);
                }
            } catch (...) {
                local_error = std::current_exception();
            }
            local_done = true;
        });
    }
    const auto stop = [&](std::string why) {
        if (!stopping) failure = std::move(why);
        stopping = true;
        local_cancel = true;
    };

    int active = size - 1;  // workers that have not had their last word
    int gathered = 0;
    double last_report = -1.0;
    std::exception_ptr gather_error;
    while (active > 0 || !local_done.load()) {
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
                        unpack_splats(sums, halves, camera, worker_splats, worker_first_splats,
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
                    if (!stopping && unpack(film, half, halves, tiling, message, source) >= 0)
                        ++gathered;
                } catch (...) {
                    stop(message_of(std::current_exception()));
                }
                stats.gather_bytes += message.size();
                stats.gather_seconds += seconds_since(t0);
                const int t = stopping ? tiling.count : next_tile.fetch_add(1);
                if (stopping) {
                    send_text(failure, source, kStop, comm);
                    --active;
                } else if (t < tiling.count) {
                    const auto t32 = static_cast<std::int32_t>(t);
                    send_bytes(&t32, sizeof t32, source, kAssign, comm);
                    ++stats.tiles_per_rank[static_cast<std::size_t>(source)];
                } else {
                    send_bytes(nullptr, 0, source, kDone, comm);
                    if (!splatting) --active;  // else its kSplats is its last word
                }
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
        if (s.render.cancel != nullptr && s.render.cancel->load() && !stopping) {
            stats.cancelled = true;
            stop("cancelled on rank 0");
        }
        if (local_done.load() && local_error && !stopping) {
            stop("rank 0 failed: " + message_of(local_error));
        }
        const double now = seconds_since(start);
        if (s.render.progress && now - last_report >= 0.1) {
            last_report = now;
            const int done = gathered + local_tiles.load();
            s.render.progress(
                {tiling.count > 0 ? static_cast<double>(done) / tiling.count : 1.0, now, 0, 0});
        }
        std::this_thread::sleep_for(size > 1 ? k_poll_interval : k_poll_interval_alone);
    }
    if (local.joinable()) local.join();
    if (local_error && failure.empty()) failure = "rank 0 failed: " + message_of(local_error);
    // Every rank's splats into the film's (integer sums: exact in any order); with kept
    // passes, the first halves' into half.splats and, with the rest, into film.splats.
    try {
        add_splats(film.splats, worker_splats);
        add_splats(half.splats, worker_first_splats);
        if (halves) add_splats(film.splats, half.splats);
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
    if (image != nullptr) *image = halves ? kept.combined(half, film) : resolve(film);
    if (s.render.progress) s.render.progress({1.0, stats.seconds, 1, spp});
    return film;
}

// Any other rank: asks rank 0 for tiles until told there are none left.
Film run_worker(MPI_Comm comm, const Scene& scene, const Camera& camera, Integrator& integrator,
                const MpiRenderSettings& s, MpiRenderStats& stats) {
    const Clock::time_point start = Clock::now();
    const Tiling tiling(camera.width(), camera.height(), std::max(1, s.tile_size));
    stats.tiles = tiling.count;
    // The finished tile the next request carries, on a film of the tile's size only: a
    // worker never holds the whole frame (32 x 32 x 96 bytes with AOVs, not 796 MB at 4K).
    Film film;
    Film half;  // with kept training passes: the tile at half its samples
    int tile = -1;
    try {
        validate(s);
        integrator.preprocess(scene);
        const RenderSettings rs = block_settings(s, s.render.cancel);
        // Not kept here (rank 0 keeps them; no whole-image sums on a worker): a pass
        // rendered in halves teaches PathTracer the same guide, as its records are integer
        // sums that no order or split changes.
        train(scene, camera, integrator, rs);
        const bool halves = keeps_halves(integrator, s);
        const bool splatting = integrator.splats();
        // A splatting integrator's splats over all this worker's tiles (of the first halves
        // in `first_splats` with `halves`): whole-image films, sent once at the end.
        std::optional<SplatFilm> splats, first_splats;
        const auto spp = static_cast<std::uint32_t>(s.render.samples_per_pixel);
        while (true) {
            const Clock::time_point t0 = Clock::now();
            const std::vector<std::byte> request = pack(film, half, halves, tile);
            send_bytes(request.data(), request.size(), 0, kRequest, comm);
            stats.gather_bytes += request.size();
            MPI_Status status;
            check(MPI_Probe(0, MPI_ANY_TAG, comm, &status), "MPI_Probe");
            const std::vector<std::byte> answer = receive(status, comm);
            stats.gather_seconds += seconds_since(t0);
            if (status.MPI_TAG == kDone) {
                if (splatting) {
                    const std::vector<std::int64_t> sums =
                        pack_splats(splats, first_splats, halves);
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
            std::int32_t t32 = -1;
            if (status.MPI_TAG != kAssign || answer.size() != sizeof t32) {
                throw Error("render_mpi: unexpected message (tag " +
                            std::to_string(status.MPI_TAG) + ") from rank 0");
            }
            std::memcpy(&t32, answer.data(), sizeof t32);
            tile = t32;
            const Rect r = tiling.rect(tile);
            film = Film(r.x1 - r.x0, r.y1 - r.y0, s.aovs);
            film.splats = std::exchange(splats, std::nullopt);
            if (halves) {
                half = Film(r.x1 - r.x0, r.y1 - r.y0);
                half.splats = std::exchange(first_splats, std::nullopt);
            }
            const RenderStats st = render_tile(scene, camera, integrator, film, {r.x0, r.y0}, r,
                                               spp, halves, half, rs);
            splats = std::exchange(film.splats, std::nullopt);
            first_splats = std::exchange(half.splats, std::nullopt);
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
    // Ranks render whole tiles with all their samples; adaptive sampling's counts come
    // from a pilot of the whole image (neighbours across tiles), which they do not share.
    if (s.render.adaptive.enabled) {
        throw Error(
            "render.adaptive.enabled = true: render_mpi samples every pixel alike; "
            "adaptive sampling needs render()");
    }
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
