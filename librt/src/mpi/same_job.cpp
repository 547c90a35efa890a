// check_same_job (mpi/same_job.h): rank 0's items are broadcast (their length, then the
// bytes), every rank compares its own with them, and check_all_ranks names the lowest rank
// that differs on every rank. Broadcasting rank 0's items, rather than gathering everyone's
// at rank 0, keeps the bytes any rank receives to one rank's items, whatever the rank count.
#include "mpi/mpi_messages.h"

#include <librt/core/error.h>
#include <librt/mpi/render_mpi.h>
#include <librt/mpi/same_job.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <exception>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace librt {

namespace {

using mpi_detail::check;

// Over this, a broadcast's int count could overflow (and a mistake is likely anyway).
constexpr std::size_t kMaxBytes = std::size_t{1} << 30;

void put(std::vector<char>& out, const std::string& text) {
    const auto n = static_cast<std::uint32_t>(std::min(text.size(), kMaxBytes));
    const std::size_t at = out.size();
    out.resize(at + sizeof n + n);
    std::memcpy(out.data() + at, &n, sizeof n);
    std::memcpy(out.data() + at + sizeof n, text.data(), n);
}

// Every item as its name's length (uint32), its name, its value's length and its value.
std::vector<char> pack(const std::vector<JobItem>& items) {
    std::vector<char> out;
    for (const JobItem& item : items) {
        put(out, item.name);
        put(out, item.value);
    }
    return out;
}

std::optional<std::string> take(std::string_view& in) {
    std::uint32_t n = 0;
    if (in.size() < sizeof n) return std::nullopt;
    std::memcpy(&n, in.data(), sizeof n);
    in.remove_prefix(sizeof n);
    if (in.size() < n) return std::nullopt;
    std::string text(in.substr(0, n));
    in.remove_prefix(n);
    return text;
}

// A value in a message: long ones cut (a user's path may be long; digests are short).
std::string shown(const std::string& value) {
    constexpr std::size_t kMax = 160;
    return value.size() <= kMax ? value : value.substr(0, kMax) + "...";
}

// What differs between this rank's items and rank 0's (`root`), empty when nothing does,
// without the "rank R: " that check_all_ranks puts before it.
std::string differences(const std::vector<JobItem>& mine, const std::vector<char>& root) {
    std::vector<JobItem> theirs;
    for (std::string_view in(root.data(), root.size()); !in.empty();) {
        std::optional<std::string> name = take(in);
        std::optional<std::string> value = name ? take(in) : std::nullopt;
        if (!value) return "rank 0's items to compare are malformed (another program?)";
        theirs.push_back({std::move(*name), std::move(*value)});
    }
    std::map<std::string_view, const std::string*> my_values;
    for (const JobItem& item : mine) my_values.try_emplace(item.name, &item.value);
    std::map<std::string_view, const std::string*> root_values;
    for (const JobItem& item : theirs) root_values.try_emplace(item.name, &item.value);
    std::string first;
    std::vector<std::string> others;
    const auto found = [&](std::string text, const std::string& name) {
        if (first.empty()) {
            first = std::move(text);
        } else {
            others.push_back(name);
        }
    };
    for (const JobItem& item : theirs) {
        if (root_values.at(item.name) != &item.value) continue;  // a repeated name
        const auto it = my_values.find(item.name);
        if (it == my_values.end()) {
            found("has no " + item.name + ", rank 0 has it (" + shown(item.value) + ")", item.name);
        } else if (*it->second != item.value) {
            found(item.name + " differs from rank 0 (" + shown(*it->second) + " vs " +
                      shown(item.value) + ")",
                  item.name);
        }
    }
    for (const JobItem& item : mine) {
        if (my_values.at(item.name) == &item.value && !root_values.contains(item.name))
            found("has " + item.name + " (" + shown(item.value) + "), rank 0 has not", item.name);
    }
    if (!others.empty()) {
        first += "; also";
        constexpr std::size_t kListed = 8;
        for (std::size_t i = 0; i < others.size() && i < kListed; ++i)
            first += (i == 0 ? " " : ", ") + others[i];
        if (others.size() > kListed)
            first += " and " + std::to_string(others.size() - kListed) + " more";
    }
    return first;
}

}  // namespace

void check_same_job(MPI_Comm comm, const std::vector<JobItem>& items) {
    int rank = 0;
    int size = 1;
    check(MPI_Comm_rank(comm, &rank), "MPI_Comm_rank");
    check(MPI_Comm_size(comm, &size), "MPI_Comm_size");
    if (size == 1) return;
    // Rank 0's items (or -1 when too large to send), then every rank's verdict on them.
    std::vector<char> root;
    int length = 0;
    if (rank == 0) {
        root = pack(items);
        length = root.size() <= kMaxBytes ? static_cast<int>(root.size()) : -1;
    }
    check(MPI_Bcast(&length, 1, MPI_INT, 0, comm), "MPI_Bcast");
    if (length < 0)
        throw Error("rank 0: the items to compare with the other ranks are over 2^30 bytes");
    root.resize(static_cast<std::size_t>(length));
    check(MPI_Bcast(root.data(), length, MPI_CHAR, 0, comm), "MPI_Bcast");
    std::string verdict;
    if (rank != 0) {
        try {
            verdict = differences(items, root);
        } catch (const std::exception& e) {
            verdict = std::string("cannot compare the job with rank 0's: ") + e.what();
        }
    }
    // How many ranks differ, so that the lowest one's message can tell.
    const int differs = verdict.empty() ? 0 : 1;
    int count = 0;
    check(MPI_Allreduce(&differs, &count, 1, MPI_INT, MPI_SUM, comm), "MPI_Allreduce");
    if (!verdict.empty() && count > 1) {
        verdict += "; " + std::to_string(count - 1) + " more rank" + (count > 2 ? "s" : "") +
                   " differ" + (count > 2 ? "" : "s");
    }
    check_all_ranks(comm, verdict);
}

}  // namespace librt
