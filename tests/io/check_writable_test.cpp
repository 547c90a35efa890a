// check_writable (issue 37, defect 5): an output that cannot be written is found before
// the work, by creating and removing a temporary where the writers would; it leaves
// nothing behind and names the path and the system's reason.

#include "io/temp_dir_test.h"
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/io/check_writable.h>
#include <librt/io/image_io.h>

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
namespace fs = std::filesystem;

namespace {

class CheckWritable : public librt::testing::TempDirTest {};

}  // namespace

TEST_F(CheckWritable, AWritableDirectoryPassesAndKeepsNothing) {
    check_writable(dir_ / "out.png");
    EXPECT_EQ(entries(), 0u);
    // An existing target is not touched (a write replaces it only at the end).
    { std::ofstream(dir_ / "old.exr") << "old"; }
    check_writable(dir_ / "old.exr");
    EXPECT_EQ(librt::testing::read_all(dir_ / "old.exr"), "old");
    EXPECT_EQ(entries(), 1u);
}

TEST_F(CheckWritable, MissingDirectoriesAndFilesUsedAsDirectoriesAreNamed) {
    const fs::path missing = dir_ / "missing" / "x.png";
    EXPECT_EQ(error_of([&] { check_writable(missing); }),
              "cannot write '" + missing.string() + "': No such file or directory");
    { std::ofstream(dir_ / "plain") << "x"; }
    const fs::path under_file = dir_ / "plain" / "x.png";
    EXPECT_EQ(error_of([&] { check_writable(under_file); }),
              "cannot write '" + under_file.string() + "': Not a directory");
    EXPECT_EQ(entries(), 1u);
}

// /sys takes no new files, not even from root (EACCES; EROFS where it is mounted
// read-only), /proc neither: both fail whoever runs the tests. Before, check_image_path
// let them through (the directory exists) and the render ran to be lost at the write.
TEST_F(CheckWritable, SysAndProcAreRefusedEvenForRoot) {
    for (const fs::path& path : std::vector<fs::path>{"/sys/librt_probe.png", "/proc/x.exr"}) {
        if (!fs::is_directory(path.parent_path())) continue;
        const std::string message = error_of([&] { check_writable(path); });
        EXPECT_EQ(message.rfind("cannot write '" + path.string() + "': ", 0), 0u) << message;
        EXPECT_GT(message.size(), ("cannot write '" + path.string() + "': ").size()) << message;
        EXPECT_EQ(error_of([&] { check_image_path(path); }), message);
        EXPECT_FALSE(fs::exists(path));
    }
}

TEST_F(CheckWritable, AReadOnlyDirectoryIsRefused) {
    const fs::path locked = dir_ / "locked";
    fs::create_directory(locked);
    fs::permissions(locked, fs::perms::owner_read | fs::perms::owner_exec);
    const bool bypassed = static_cast<bool>(std::ofstream(locked / "probe"));
    if (bypassed) {
        fs::remove(locked / "probe");
        fs::permissions(locked, fs::perms::owner_all);
        GTEST_SKIP() << "running with permission override (root?): a read-only directory "
                        "is writable here, so that case cannot be tested";
    }
    EXPECT_EQ(error_of([&] { check_writable(locked / "x.png"); }),
              "cannot write '" + (locked / "x.png").string() + "': Permission denied");
    EXPECT_TRUE(fs::is_empty(locked));
    fs::permissions(locked, fs::perms::owner_all);
}
