// FNV-1a 64 (core/fnv1a.h) against the published test vectors, and file_digest over files
// of several blocks and over files it cannot read.
#include "robustness/robustness_util.h"

#include <librt/core/error.h>
#include <librt/core/fnv1a.h>
#include <librt/io/file_digest.h>

#include <gtest/gtest.h>

#include <cstddef>
#include <string>

using namespace librt;
using librt::testing::ScratchDir;

// Vectors from the FNV reference test suite (http://www.isthe.com/chongo/src/fnv/test_fnv.c).
TEST(Fnv1a64, MatchesTheReferenceVectors) {
    static_assert(fnv1a64(std::string_view{}) == 0xcbf29ce484222325ULL);
    EXPECT_EQ(fnv1a64(std::string_view("a")), 0xaf63dc4c8601ec8cULL);
    EXPECT_EQ(fnv1a64(std::string_view("foobar")), 0x85944171f73967e8ULL);
}

TEST(Fnv1a64, ContinuedOverPiecesIsTheDigestOfTheWhole) {
    EXPECT_EQ(fnv1a64(std::string_view("bar"), fnv1a64(std::string_view("foo"))),
              fnv1a64(std::string_view("foobar")));
}

TEST(FileDigest, IsTheDigestOfEveryByteOverSeveralBlocks) {
    const ScratchDir dir;
    // 2.5 MiB with NULs: three blocks of file_digest's 1 MiB, the last one short.
    std::string bytes((std::size_t{5} << 20) / 2, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>((i * 7919) >> 3);
    const FileDigest d = file_digest(dir.write("big.bin", bytes));
    EXPECT_EQ(d.bytes, bytes.size());
    EXPECT_EQ(d.fnv1a64, fnv1a64(bytes));
    // One byte changed in the last block changes it.
    bytes.back() = static_cast<char>(bytes.back() ^ 1);
    EXPECT_NE(file_digest(dir.write("changed.bin", bytes)).fnv1a64, d.fnv1a64);
    const FileDigest empty = file_digest(dir.write("empty.bin", ""));
    EXPECT_EQ(empty.bytes, 0u);
    EXPECT_EQ(empty.fnv1a64, kFnv1a64Offset);
    EXPECT_EQ(to_string(empty), "fnv1a64 cbf29ce484222325, 0 bytes");
}

TEST(FileDigest, OfBytesInMemoryIsTheDigestOfAFileHoldingThem) {
    // What the loaders take from the bytes they read must equal what a separate read gives.
    const ScratchDir dir;
    std::string bytes(3000, '\0');
    for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<char>(i * 131);
    const FileDigest in_memory = digest_of(bytes);
    const FileDigest from_file = file_digest(dir.write("bytes.bin", bytes));
    EXPECT_EQ(in_memory.fnv1a64, from_file.fnv1a64);
    EXPECT_EQ(in_memory.bytes, 3000u);
    EXPECT_EQ(to_string(digest_of("")), "fnv1a64 cbf29ce484222325, 0 bytes");
}

TEST(FileDigest, NamesTheFileItCannotRead) {
    const ScratchDir dir;
    const auto message = [](const std::filesystem::path& p) {
        try {
            (void)file_digest(p);
        } catch (const Error& e) {
            return std::string(e.what());
        }
        return std::string("no error");
    };
    const std::string missing = message(dir.path() / "missing.obj");
    EXPECT_NE(missing.find("missing.obj: cannot open the file"), std::string::npos) << missing;
    const std::string directory = message(dir.path());
    EXPECT_NE(directory.find(dir.path().string() + ": cannot"), std::string::npos) << directory;
}
