#pragma once

// render_mpi's messages (the protocol is described at the top of render_mpi.cpp): the
// tiling, a tile's records packed into a message and back, the splat sums, and thin
// wrappers of MPI's send and receive that throw librt::Error. Internal to librt::mpi.

#include <librt/film/camera.h>
#include <librt/film/film.h>
#include <librt/film/splat_film.h>

#include <mpi.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <vector>

namespace librt::mpi_detail {

enum Tag : int {
    kRequest = 1,
    kFail = 2,
    kCancel = 3,
    kAssign = 4,
    kDone = 5,
    kStop = 6,
    kSplats = 7
};

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

/// Throws librt::Error naming `call` and MPI's message unless rc is MPI_SUCCESS.
void check(int rc, const char* call);

/// Bytes per pixel of a tile's records: its FilmPixel, its AovPixel with AOVs, and its
/// FilmPixel at half the samples with `halves`.
std::size_t record_bytes(const Film& film, bool halves);

/// A kRequest message: the job index (-1: none yet), then the tile's records (`tile` is a
/// film of the tile's size, so its records are the tile's rows in order), then its AOV
/// records, then with `halves` the records of `half` (the tile at half its samples).
std::vector<std::byte> pack(const Film& tile, const Film& half, bool halves, int index);

/// Copies a kRequest's records into `film` (and `half`) and returns its job (-1 for none).
/// Jobs are [0, jobs): job t < tiling.count renders tile t from no samples, its records
/// carrying the half when `halves`; with jobs = 2 tiling.count (adaptive sampling), job
/// tiling.count + t continues tile t to its pixels' counts and carries no half.
int unpack(Film& film, Film& half, bool halves, const Tiling& tiling, int jobs,
           const std::vector<std::byte>& message, int source);

/// A kAssign message: the job; for a job that continues a tile (job >= tiling.count), the
/// tile's records as `film` (the whole image) holds them, its AOV records, and each pixel's
/// count from `counts` (one per image pixel), row by row.
std::vector<std::byte> pack_assignment(int job, const Tiling& tiling, const Film& film,
                                       const std::vector<std::uint32_t>& counts);

/// Reads a kAssign message on a worker: returns the job and makes `tile` a film of the
/// tile's size (with AOVs when `aovs`); for a continuing job, holding the records sent and
/// with `ends` the counts (else `ends` is emptied). Throws librt::Error for a malformed one.
int unpack_assignment(const std::vector<std::byte>& message, const Tiling& tiling, bool aovs,
                      Film& tile, std::vector<std::uint32_t>& ends);

/// The message of an exception, for a kFail or kStop.
std::string message_of(const std::exception_ptr& error);

void send_bytes(const void* data, std::size_t size, int dest, int tag, MPI_Comm comm);
void send_text(const std::string& text, int dest, int tag, MPI_Comm comm);
/// Receives the message `status` announced (from MPI_Probe / MPI_Iprobe).
std::vector<std::byte> receive(const MPI_Status& status, MPI_Comm comm);
void send_int64s(const std::vector<std::int64_t>& data, int dest, int tag, MPI_Comm comm);
std::vector<std::int64_t> receive_int64s(const MPI_Status& status, MPI_Comm comm);

/// A kSplats message: the sums and counts of `splats` (a worker's second halves with
/// `halves`, else everything), then with `halves` those of `first` (its first halves).
/// Empty when the worker has none.
std::vector<std::int64_t> pack_splats(const std::optional<SplatFilm>& splats,
                                      const std::optional<SplatFilm>& first, bool halves);

/// Adds a kSplats message to `rest` and (with `halves`) `first`, creating them as the
/// render loop creates a film's splats (splat_filter_settings, the default scale).
void unpack_splats(const std::vector<std::int64_t>& message, bool halves, const Camera& camera,
                   std::optional<SplatFilm>& rest, std::optional<SplatFilm>& first, int source);

/// Adds `from` to `into` (SplatFilm::merge), or copies it when `into` has none.
void add_splats(std::optional<SplatFilm>& into, const std::optional<SplatFilm>& from);

std::string text_of(const std::vector<std::byte>& data);

}  // namespace librt::mpi_detail
