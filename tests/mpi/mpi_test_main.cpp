// main() of librt_mpi_tests: GoogleTest inside an MPI job (alone it is a job of one rank,
// Open MPI's singleton). Only rank 0 prints the results; every rank runs every test, since
// render_mpi is collective.
#include <gtest/gtest.h>

#include <mpi.h>

#include <string_view>

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
    }
    const int failed = RUN_ALL_TESTS();
    // A test that failed on any rank fails the job.
    int any = failed != 0 ? 1 : 0;
    int all = 0;
    MPI_Allreduce(&any, &all, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    MPI_Finalize();
    return all;
}
