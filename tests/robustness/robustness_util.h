#pragma once

// Helpers shared by the bad-input tests: a scratch directory, "the message of the error
// this throws", and whether file permissions can block reads here (not as root).

#include <librt/core/error.h>

#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace librt::testing {

/// A fresh directory under the system temp dir, removed (permissions restored first) with
/// everything in it.
class ScratchDir {
public:
    ScratchDir() {
        static std::atomic<int> counter{0};
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        path_ = std::filesystem::temp_directory_path() /
                ("librt_robust_" + std::string(info ? info->name() : "x") + "_" +
                 std::to_string(::getpid()) + "_" + std::to_string(counter++));
        std::filesystem::remove_all(path_);
        std::filesystem::create_directories(path_);
    }
    ~ScratchDir() {
        std::error_code ignored;
        for (const auto& entry : std::filesystem::recursive_directory_iterator(path_, ignored))
            std::filesystem::permissions(entry.path(), std::filesystem::perms::owner_all,
                                         std::filesystem::perm_options::add, ignored);
        std::filesystem::remove_all(path_, ignored);
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;

    /// Writes bytes (any, NULs included) to `name` inside the directory; returns its path.
    std::filesystem::path write(const std::string& name, std::string_view bytes) const {
        const std::filesystem::path p = path_ / name;
        std::ofstream out(p, std::ios::binary);
        out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
        return p;
    }
    [[nodiscard]] const std::filesystem::path& path() const { return path_; }
    /// Names of the entries in the directory (dot files included), sorted, space-separated.
    [[nodiscard]] std::string listing() const {
        std::vector<std::string> names;
        for (const auto& entry : std::filesystem::directory_iterator(path_))
            names.push_back(entry.path().filename().string());
        std::sort(names.begin(), names.end());
        std::string out;
        for (const std::string& n : names) {
            if (!out.empty()) out += ' ';
            out += n;
        }
        return out;
    }

private:
    std::filesystem::path path_;
};

/// The message of the librt::Error `f` throws; "" (and a test failure) if it throws
/// nothing. Any other exception type propagates and fails the test.
template <class F>
std::string error_of(F&& f) {
    try {
        f();
    } catch (const Error& e) {
        return e.what();
    }
    ADD_FAILURE() << "expected a librt::Error";
    return "";
}

/// All warnings as one string, one a line, for searching and for failure messages.
inline std::string joined(const std::vector<std::string>& warnings) {
    std::string all;
    for (const std::string& w : warnings) {
        all += w;
        all += '\n';
    }
    return all;
}

/// True when `text` contains `part`.
inline bool has(const std::string& text, std::string_view part) {
    return text.find(part) != std::string::npos;
}

/// True when permission bits do not stop this process from reading (root, or
/// CAP_DAC_OVERRIDE): a chmod 000 file is then still readable.
inline bool permissions_are_bypassed(const std::filesystem::path& unreadable_file) {
    std::ifstream probe(unreadable_file, std::ios::binary);
    return static_cast<bool>(probe);
}

}  // namespace librt::testing

/// Skips the rest of the test, visibly, when `file` (made unreadable with chmod 000) can
/// still be read: running as root, permissions do not block reads.
#define LIBRT_SKIP_IF_PERMISSIONS_BYPASSED(file)                                              \
    if (::librt::testing::permissions_are_bypassed(file)) {                                   \
        GTEST_SKIP() << "running with permission override (root?): chmod 000 does not block " \
                        "reads here, so the unreadable-file case cannot be tested";           \
    }
