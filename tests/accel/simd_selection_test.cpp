// The SIMD path choice as a query: a LIBRT_SIMD request is followed when this CPU supports
// it, otherwise the best path is used and the note says why (the library prints nothing).

#include <librt/accel/simd.h>

#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

using namespace librt;

namespace {

constexpr SimdPath kAllPaths[] = {SimdPath::Scalar, SimdPath::Sse, SimdPath::Avx2,
                                  SimdPath::Avx512};

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

}  // namespace

TEST(SimdSelection, NoRequestOrAutoTakesTheBestPathSilently) {
    const SimdPath best = supported_simd_paths().back();
    for (const char* request : {"", "auto"}) {
        const SimdSelection s = select_simd_path(request);
        EXPECT_EQ(s.path, best) << request;
        EXPECT_EQ(s.requested, request);
        EXPECT_TRUE(s.note.empty()) << s.note;
    }
}

TEST(SimdSelection, ASupportedRequestIsFollowedAndAnUnsupportedOneExplained) {
    const SimdPath best = supported_simd_paths().back();
    for (const SimdPath p : kAllPaths) {
        const SimdSelection s = select_simd_path(to_string(p));
        EXPECT_EQ(s.requested, to_string(p));
        if (simd_path_supported(p)) {
            EXPECT_EQ(s.path, p) << to_string(p);
            EXPECT_TRUE(s.note.empty()) << s.note;
        } else {
            EXPECT_EQ(s.path, best) << to_string(p);
            EXPECT_TRUE(contains(s.note, std::string("LIBRT_SIMD=") + to_string(p) +
                                             " is not supported here, using " + to_string(best)))
                << s.note;
        }
    }
}

TEST(SimdSelection, AnUnknownNameIsExplainedWithTheValidNames) {
    const SimdPath best = supported_simd_paths().back();
    for (const char* request : {"avx3", "AVX2", " sse", "neon"}) {
        const SimdSelection s = select_simd_path(request);
        EXPECT_EQ(s.path, best) << request;
        EXPECT_TRUE(contains(s.note, std::string("LIBRT_SIMD=") + request +
                                         " is not one of auto, scalar, sse, avx2, avx512; using " +
                                         to_string(best)))
            << s.note;
    }
}

TEST(SimdSelection, TheProcessWideChoiceIsTheSelectionOfTheEnvironment) {
    const char* env = std::getenv("LIBRT_SIMD");
    const SimdSelection expected = select_simd_path(env ? env : "");
    EXPECT_EQ(simd_selection().path, expected.path);
    EXPECT_EQ(simd_selection().requested, expected.requested);
    EXPECT_EQ(simd_selection().note, expected.note);
    EXPECT_EQ(default_simd_path(), simd_selection().path);
    EXPECT_EQ(&simd_path_note(), &simd_selection().note);
    EXPECT_TRUE(simd_path_supported(default_simd_path()));
}
