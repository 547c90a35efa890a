// main() of librt_mpi_tests: GoogleTest inside an MPI job (alone it is a job of one rank,
// Open MPI's singleton). Rank 0 prints the results, the other ranks only their failures;
// every rank runs every test, since render_mpi is collective.
#include <gtest/gtest.h>

#include <mpi.h>

#include <cstdio>
#include <string_view>

namespace {

// A failed check on a rank other than 0 fails the whole job (below): print it, with the
// rank, or the job fails with nothing shown.
class FailurePrinter final : public ::testing::EmptyTestEventListener {
public:
    explicit FailurePrinter(int rank) : rank_(rank) {}
    void OnTestPartResult(const ::testing::TestPartResult& result) override {
        if (!result.failed()) return;
        const ::testing::TestInfo* test = ::testing::UnitTest::GetInstance()->current_test_info();
        std::fprintf(stderr, "rank %d: %s.%s failed at %s:%d\n%s\n", rank_,
                     test != nullptr ? test->test_suite_name() : "?",
                     test != nullptr ? test->name() : "?",
                     result.file_name() != nullptr ? result.file_name() : "?", result.line_number(),
                     result.message());
        std::fflush(stderr);
    }

private:
    int rank_;
};

}  // namespace

int main(int argc, char** argv) {
    // Listing the tests (gtest_discover_tests, at build time) needs no MPI. Starting Open MPI
    // there would put its exit-time leaks before LeakSanitizer in the asan build, which fails
    // the build itself.
    for (int i = 1; i < argc; ++i) {
        if (std::string_view(argv[i]) == "--gtest_list_tests") {
            ::testing::InitGoogleTest(&argc, argv);
            return RUN_ALL_TESTS();
        }
    }
    int provided = 0;
    MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
    ::testing::InitGoogleTest(&argc, argv);
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank != 0) {
        ::testing::TestEventListeners& listeners = ::testing::UnitTest::GetInstance()->listeners();
        delete listeners.Release(listeners.default_result_printer());
        listeners.Append(new FailurePrinter(rank));  // the listeners own it
    }
    const int failed = RUN_ALL_TESTS();
    // A test that failed on any rank fails the job.
    int any = failed != 0 ? 1 : 0;
    int all = 0;
    MPI_Allreduce(&any, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return all;
}
