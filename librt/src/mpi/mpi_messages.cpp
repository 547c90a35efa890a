// render_mpi's messages (render_mpi.cpp describes the protocol): packing a tile's records
// and the splat sums into messages and back, and thin wrappers of MPI's send and receive
// that throw librt::Error.

#include "mpi/mpi_messages.h"

#include "film/camera_importance.h"

#include <librt/core/error.h>

#include <algorithm>
#include <cstring>
#include <limits>
#include <type_traits>

namespace librt::mpi_detail {

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

std::size_t record_bytes(const Film& film, bool halves) {
    return sizeof(FilmPixel) + (film.has_aovs() ? sizeof(AovPixel) : 0) +
           (halves ? sizeof(FilmPixel) : 0);
}

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

int unpack(Film& film, Film& half, bool halves, const Tiling& tiling, int jobs,
           const std::vector<std::byte>& message, int source) {
    std::int32_t index = -1;
    if (message.size() < sizeof index)
        throw Error("render_mpi: short message from rank " + std::to_string(source));
    std::memcpy(&index, message.data(), sizeof index);
    if (index < 0) return -1;
    const bool with_half = halves && index < tiling.count;
    const Rect r = tiling.rect(index % tiling.count);
    if (index >= jobs ||
        message.size() != sizeof index + r.pixels() * record_bytes(film, with_half)) {
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
    if (with_half) {
        for (int y = r.y0; y < r.y1; ++y) {
            std::memcpy(&half.pixels[half.index(r.x0, y)], at, row * sizeof(FilmPixel));
            at += row * sizeof(FilmPixel);
        }
    }
    return index;
}

std::vector<std::byte> pack_assignment(int job, const Tiling& tiling, const Film& film,
                                       const std::vector<std::uint32_t>& counts) {
    const auto job32 = static_cast<std::int32_t>(job);
    std::vector<std::byte> out(sizeof job32);
    std::memcpy(out.data(), &job32, sizeof job32);
    if (job < tiling.count) return out;
    const Rect r = tiling.rect(job - tiling.count);
    const auto row = static_cast<std::size_t>(r.x1 - r.x0);
    out.resize(out.size() + r.pixels() * (record_bytes(film, false) + sizeof(std::uint32_t)));
    std::byte* at = out.data() + sizeof job32;
    for (int y = r.y0; y < r.y1; ++y) {
        std::memcpy(at, &film.pixels[film.index(r.x0, y)], row * sizeof(FilmPixel));
        at += row * sizeof(FilmPixel);
    }
    if (film.has_aovs()) {
        for (int y = r.y0; y < r.y1; ++y) {
            std::memcpy(at, &film.aovs[film.index(r.x0, y)], row * sizeof(AovPixel));
            at += row * sizeof(AovPixel);
        }
    }
    for (int y = r.y0; y < r.y1; ++y) {
        std::memcpy(at, &counts[film.index(r.x0, y)], row * sizeof(std::uint32_t));
        at += row * sizeof(std::uint32_t);
    }
    return out;
}

int unpack_assignment(const std::vector<std::byte>& message, const Tiling& tiling, bool aovs,
                      Film& tile, std::vector<std::uint32_t>& ends) {
    std::int32_t job = -1;
    if (message.size() < sizeof job) throw Error("render_mpi: short assignment from rank 0");
    std::memcpy(&job, message.data(), sizeof job);
    const auto malformed = [&] {
        return Error("render_mpi: rank 0 assigned job " + std::to_string(job) +
                     " in a message of " + std::to_string(message.size()) +
                     " bytes (mismatched settings?)");
    };
    if (job < 0 || job >= 2 * tiling.count) throw malformed();
    const bool continues = job >= tiling.count;
    const Rect r = tiling.rect(job % tiling.count);
    const std::size_t n = r.pixels();
    const std::size_t per_pixel =
        sizeof(FilmPixel) + (aovs ? sizeof(AovPixel) : 0) + sizeof(std::uint32_t);
    if (message.size() != sizeof job + (continues ? n * per_pixel : 0)) throw malformed();
    tile = Film(r.x1 - r.x0, r.y1 - r.y0, aovs);
    ends.clear();
    if (!continues) return job;
    const std::byte* at = message.data() + sizeof job;
    std::memcpy(tile.pixels.data(), at, n * sizeof(FilmPixel));
    at += n * sizeof(FilmPixel);
    if (aovs) {
        std::memcpy(tile.aovs.data(), at, n * sizeof(AovPixel));
        at += n * sizeof(AovPixel);
    }
    ends.resize(n);
    std::memcpy(ends.data(), at, n * sizeof(std::uint32_t));
    return job;
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

namespace {

// Receives the message `status` announced as elements of T (MPI type `type`).
template <class T>
std::vector<T> receive_as(const MPI_Status& status, MPI_Comm comm, MPI_Datatype type) {
    int count = 0;
    check(MPI_Get_count(&status, type, &count), "MPI_Get_count");
    std::vector<T> data(static_cast<std::size_t>(count));
    check(MPI_Recv(data.data(), count, type, status.MPI_SOURCE, status.MPI_TAG, comm,
                   MPI_STATUS_IGNORE),
          "MPI_Recv");
    return data;
}

}  // namespace

std::vector<std::byte> receive(const MPI_Status& status, MPI_Comm comm) {
    return receive_as<std::byte>(status, comm, MPI_BYTE);
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
    return receive_as<std::int64_t>(status, comm, MPI_INT64_T);
}

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

}  // namespace librt::mpi_detail
