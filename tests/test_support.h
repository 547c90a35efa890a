#pragma once

#include <gtest/gtest.h>

#include <filesystem>
#include <optional>
#include <string>

namespace librt::testing {

/// Directory of the real meshes: $LIBRT_DATA_DIR, else the configured default (../shared/data).
std::filesystem::path data_dir();

/// True when $LIBRT_REQUIRE_DATA is set to 1 (CI): missing data then fails instead of skipping.
bool data_required();

}  // namespace librt::testing

/// Resolves a data file into `var`; when the file is missing the test skips with a
/// visible message, or fails when LIBRT_REQUIRE_DATA=1 (as .ci/run sets it).
#define LIBRT_REQUIRE_DATA_FILE(var, name)                                   \
    const std::filesystem::path var = ::librt::testing::data_dir() / (name); \
    if (!std::filesystem::is_regular_file(var)) {                            \
        if (::librt::testing::data_required()) {                             \
            FAIL() << "required data file missing: " << var                  \
                   << " (set LIBRT_DATA_DIR or provide ../shared/data)";     \
        } else {                                                             \
            GTEST_SKIP() << "data file missing, test skipped: " << var       \
                         << " (set LIBRT_DATA_DIR to run it)";               \
        }                                                                    \
    }
