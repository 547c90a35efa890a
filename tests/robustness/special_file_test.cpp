// Issue 10, defects 2, 3 and 7: files that are not regular files, files too large to read,
// and writes killed half-way. Every path librt reads goes through one reader that opens
// regular files only, bounded; every writer goes through one atomic writer.

#include "robustness/robustness_util.h"

#include <librt/io/image_io.h>
#include <librt/io/texture_io.h>
#include <librt/obj/obj.h>

#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

using namespace librt;
using librt::testing::error_of;
using librt::testing::has;
using librt::testing::ScratchDir;
namespace fs = std::filesystem;

namespace {

const std::string kTriangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";

/// Bytes this process has passed through read() so far (/proc/self/io's rchar), or
/// kUnknownBytesRead where the kernel does not say.
constexpr std::uint64_t kUnknownBytesRead = ~std::uint64_t{0};
std::uint64_t bytes_read_by_this_process() {
    std::ifstream io("/proc/self/io");
    std::string key;
    std::uint64_t value = 0;
    while (io >> key >> value) {
        if (key == "rchar:") return value;
    }
    return kUnknownBytesRead;
}

std::vector<std::string> no_warnings;

TriangleMesh load(const fs::path& p) {
    ObjLoadOptions options;
    options.warnings = &no_warnings;
    return load_obj(p, options);
}

}  // namespace

// A load that blocked on the FIFO (an open without O_NONBLOCK waits for a writer forever)
// would hang here, and the test's ctest TIMEOUT fail it: no waiting time in the test.
TEST(BadFile, FifoAsMeshMtlTextureOrImageIsRefusedNotBlockedOn) {
    ScratchDir dir;
    const fs::path fifo = dir.path() / "pipe";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    // The mesh itself.
    std::string msg = error_of([&] { (void)load(fifo); });
    EXPECT_TRUE(has(msg, fifo.string() + ": is a FIFO (named pipe), not an OBJ file")) << msg;
    // mtllib naming the FIFO.
    const fs::path obj = dir.write("m.obj", "mtllib pipe\nusemtl x\n" + kTriangle);
    msg = error_of([&] { (void)load(obj); });
    EXPECT_TRUE(has(msg, fifo.string() + ": is a FIFO (named pipe), not an MTL file")) << msg;
    // A texture (map_Kd is loaded through ImageTexture::load) and a PFM.
    msg = error_of([&] { (void)load_texture(fifo); });
    EXPECT_TRUE(has(msg, "cannot load texture " + fifo.string() + ": is a FIFO")) << msg;
    msg = error_of([&] { (void)read_pfm(fifo); });
    EXPECT_TRUE(has(msg, fifo.string() + ": is a FIFO")) << msg;
}

TEST(BadFile, DevicesAreRefusedByWhatTheyAre) {
    // /dev/zero never ends (it used to end in std::bad_alloc), /dev/null is empty.
    for (const char* device : {"/dev/zero", "/dev/null"}) {
        if (!fs::exists(device)) GTEST_SKIP() << device << " does not exist here";
        const fs::path p = device;
        std::string msg = error_of([&] { (void)load(p); });
        EXPECT_TRUE(has(msg, std::string(device) + ": is a character device, not an OBJ file"))
            << msg;
        msg = error_of([&] { (void)load_texture(p); });
        EXPECT_TRUE(has(msg, "is a character device")) << msg;
    }
}

TEST(BadFile, HugeSparseObjIsRefusedByItsFirstBytesOrItsSize) {
    ScratchDir dir;
    // 2 GB of zeros (sparse: no disk used), under the 2 GiB default limit: refused by the
    // NUL byte in its first block, not after reading 2 GB (it took 47 s and 2.1 GB).
    const fs::path sparse = dir.path() / "sparse.obj";
    {
        const int fd = ::open(sparse.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0600);
        ASSERT_GE(fd, 0);
        const bool sized = ::ftruncate(fd, 2'000'000'000) == 0;
        ::close(fd);
        if (!sized) GTEST_SKIP() << "this file system cannot make a 2 GB sparse file";
    }
    const std::uint64_t read_before = bytes_read_by_this_process();
    std::string msg = error_of([&] { (void)load(sparse); });
    const std::uint64_t read = bytes_read_by_this_process() - read_before;
    EXPECT_TRUE(has(msg, sparse.string() + ":1: NUL byte in column 1")) << msg;
    if (read_before != kUnknownBytesRead) {
        EXPECT_LE(read, std::uint64_t{1} << 20) << "the whole file was read first";
    }
    // Above the limit: refused from its size, before reading, naming the option.
    ASSERT_EQ(::truncate(sparse.c_str(), (std::int64_t{1} << 31) + 1), 0);
    msg = error_of([&] { (void)load(sparse); });
    EXPECT_TRUE(has(msg,
                    "2147483649 bytes, more than the limit of 2147483648 bytes for an OBJ "
                    "file (raise ObjLoadOptions::max_file_bytes"))
        << msg;
    // The limit is an option: a valid file above a lowered limit is refused, then read.
    const fs::path small = dir.write("small.obj", kTriangle);
    ObjLoadOptions options;
    options.warnings = &no_warnings;
    options.max_file_bytes = 10;
    msg = error_of([&] { (void)load_obj(small, options); });
    EXPECT_TRUE(has(msg, "small.obj: 32 bytes, more than the limit of 10 bytes")) << msg;
    options.max_file_bytes = 32;
    EXPECT_EQ(load_obj(small, options).triangle_count(), 1u);
}

TEST(BadFile, OutputNamesUpTo255BytesWork) {
    ScratchDir dir;
    const Image image(4, 4);
    // 255 bytes is the longest legal name (NAME_MAX); the temporary used to add 24 bytes.
    for (const std::string ext : {".png", ".pfm", ".hdr"}) {
        const std::string name = std::string(255 - ext.size(), 'n') + ext;
        ASSERT_EQ(name.size(), 255u);
        write_image(dir.path() / name, image);
        EXPECT_TRUE(fs::is_regular_file(dir.path() / name)) << ext;
    }
    TriangleMesh mesh = load(dir.write("t.obj", kTriangle));
    mesh.materials.clear();
    mesh.material_ids.clear();
    const std::string obj_name = std::string(251, 'o') + ".obj";
    save_obj(mesh, dir.path() / obj_name);
    EXPECT_EQ(load(dir.path() / obj_name).triangle_count(), 1u);
    // Nothing but the outputs (no temporary) is left.
    for (const auto& entry : fs::directory_iterator(dir.path())) {
        EXPECT_NE(entry.path().filename().string().front(), '.') << entry.path();
    }
}

TEST(BadFile, WriteKilledByTheFileSizeLimitLeavesNoTemporaryAndTheOldFile) {
    ScratchDir dir;
    const fs::path out = dir.path() / "render.pfm";
    write_pfm(out, Image(2, 2));
    const auto old_size = fs::file_size(out);
    // A child writes a 256 x 256 PFM (786 KB) under a 64 KiB file-size limit: the kernel
    // kills it with SIGXFSZ half-way through its write, as a full disk quota or a SIGKILL
    // would. Before, the named temporary ".render.pfm.tmp-..." stayed behind with 64 KiB.
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
        const rlimit no_core{0, 0};
        ::setrlimit(RLIMIT_CORE, &no_core);
        const rlimit limit{64 * 1024, 64 * 1024};
        ::setrlimit(RLIMIT_FSIZE, &limit);
        ::signal(SIGXFSZ, SIG_DFL);
        try {
            write_pfm(out, Image(256, 256));
        } catch (...) {
            ::_exit(3);
        }
        ::_exit(0);
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the write was expected to be killed";
    EXPECT_EQ(WTERMSIG(status), SIGXFSZ);
    EXPECT_EQ(dir.listing(), "render.pfm");
    EXPECT_EQ(fs::file_size(out), old_size);
    EXPECT_EQ(read_pfm(out).width, 2);
}
