// check_same_job (mpi/same_job.h) inside whatever MPI job runs this binary: alone (nothing
// to compare), under mpirun -np 2 and -np 3. Ranks given different items must all throw the
// same message, naming the lowest differing rank and the item, and none may be left waiting
// (a rank that hangs fails the test by ctest's timeout).
#include <librt/core/error.h>
#include <librt/mpi/same_job.h>

#include <gtest/gtest.h>

#include <mpi.h>

#include <string>
#include <vector>

using namespace librt;

namespace {

int world_rank() {
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    return rank;
}

int world_size() {
    int size = 1;
    MPI_Comm_size(MPI_COMM_WORLD, &size);
    return size;
}

std::vector<JobItem> job(const std::string& integrator, const std::string& spp = "16") {
    return {{"scene file", "fnv1a64 0123456789abcdef, 121 bytes"},
            {"--integrator", integrator},
            {"--spp", spp}};
}

// The message check_same_job throws on this rank, or "" when it returns.
std::string failure(const std::vector<JobItem>& items) {
    try {
        check_same_job(MPI_COMM_WORLD, items);
    } catch (const Error& e) {
        return e.what();
    }
    return {};
}

}  // namespace

TEST(SameJob, AgreeingRanksPass) {
    EXPECT_EQ(failure(job("path")), "");
    EXPECT_EQ(failure({}), "");
}

// The last rank alone differs: every rank says so, in the same words.
TEST(SameJob, ADifferentValueFailsOnEveryRankNamingRankAndItem) {
    const int last = world_size() - 1;
    const std::string message = failure(job(world_rank() == last ? "bdpt" : "path"));
    if (world_size() == 1) {
        EXPECT_EQ(message, "");  // alone: nothing to compare
        return;
    }
    EXPECT_EQ(message,
              "rank " + std::to_string(last) + ": --integrator differs from rank 0 (bdpt vs path)");
}

// Every rank but 0 differs, rank 1 in two items: the lowest rank is named, with its other
// item and the number of other ranks that differ.
TEST(SameJob, SeveralDifferencesAreCounted) {
    if (world_size() == 1) GTEST_SKIP() << "needs ranks to compare";
    const int rank = world_rank();
    const std::string message =
        failure(rank == 0 ? job("path") : job("bdpt", rank == 1 ? "8" : "16"));
    std::string expected = "rank 1: --integrator differs from rank 0 (bdpt vs path); also --spp";
    if (world_size() == 3) expected += "; 1 more rank differs";
    EXPECT_EQ(message, expected);
}

// Items that disagree in number (another version of a program, an option that adds an
// item) fail the same way, whichever side has more.
TEST(SameJob, ItemsMissingOrExtraFailOnEveryRank) {
    if (world_size() == 1) GTEST_SKIP() << "needs ranks to compare";
    const int last = world_size() - 1;
    std::vector<JobItem> fewer = job("path");
    fewer.pop_back();
    EXPECT_EQ(failure(world_rank() == last ? fewer : job("path")),
              "rank " + std::to_string(last) + ": has no --spp, rank 0 has it (16)");
    std::vector<JobItem> more = job("path");
    more.push_back({"--env", "fnv1a64 00000000000000ff, 9 bytes"});
    EXPECT_EQ(failure(world_rank() == last ? more : job("path")),
              "rank " + std::to_string(last) +
                  ": has --env (fnv1a64 00000000000000ff, 9 bytes), rank 0 has not");
    // Rank 0 with none at all.
    EXPECT_EQ(failure(world_rank() == 0 ? std::vector<JobItem>{} : job("path")),
              "rank 1: has scene file (fnv1a64 0123456789abcdef, 121 bytes), rank 0 has not; "
              "also --integrator, --spp" +
                  std::string(world_size() == 3 ? "; 1 more rank differs" : ""));
}

// Values may hold any bytes (a digest, a path with spaces, NULs): compared whole, cut when
// shown.
TEST(SameJob, LongValuesAreComparedWholeAndShownCut) {
    if (world_size() == 1) GTEST_SKIP() << "needs ranks to compare";
    std::string value(1000, 'x');
    value += world_rank() == 1 ? std::string("\0a", 2) : std::string("\0b", 2);
    const std::string message = failure({{"--output", value}});
    EXPECT_EQ(message, "rank 1: --output differs from rank 0 (" + std::string(160, 'x') +
                           "... vs " + std::string(160, 'x') + "...)");
}
