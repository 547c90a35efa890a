#pragma once

// A test fixture owning a fresh, empty directory under the system temp dir (named after
// the test, so parallel ctest runs of different tests never share one), removed after the
// test; for the tests of the writers, which check what a directory holds afterwards.

#include <gtest/gtest.h>

#include <cstddef>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

namespace librt::testing {

/// Base fixture: dir_ is created empty by SetUp and removed by TearDown.
class TempDirTest : public ::testing::Test {
protected:
    void SetUp() override {
        namespace fs = std::filesystem;
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               (std::string("librt_") + info->test_suite_name() + "_" + info->name() + "_" +
                std::to_string(std::hash<std::string>{}(fs::current_path().string())));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { std::filesystem::remove_all(dir_); }

    /// Number of entries in dir_ (a writer that failed must leave none behind).
    [[nodiscard]] std::size_t entries() const {
        return static_cast<std::size_t>(std::distance(std::filesystem::directory_iterator(dir_),
                                                      std::filesystem::directory_iterator()));
    }

    std::filesystem::path dir_;
};

/// The whole content of a file ("" when it cannot be read).
[[nodiscard]] inline std::string read_all(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

}  // namespace librt::testing
