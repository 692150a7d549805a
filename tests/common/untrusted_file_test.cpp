// SPDX-License-Identifier: Apache-2.0
// UntrustedFile: regular files only (a FIFO, /dev/zero, a directory are refused at once, named),
// the kind's cap checked on the size before reading (a sparse file of any size costs nothing),
// reads bounded by the cap when the file grows, and every error naming the file and the kind.
#include "navmap/common/untrusted_file.h"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace {

using navmap::FileKind;
using navmap::UntrustedFile;

constexpr FileKind kTestKind{"test file", 100};

class UntrustedFileTest : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = std::filesystem::temp_directory_path() / ("navmap-untrusted-" + std::to_string(::getpid()));
        std::filesystem::remove_all(m_dir);
        std::filesystem::create_directories(m_dir);
    }
    void TearDown() override { std::filesystem::remove_all(m_dir); }
    std::filesystem::path write(const std::string& name, const std::string& bytes) {
        const auto p = m_dir / name;
        std::ofstream(p, std::ios::binary) << bytes;
        return p;
    }
    std::filesystem::path m_dir;
};

TEST_F(UntrustedFileTest, ARegularFileIsReadWhole) {
    const auto p = write("a.txt", std::string("line one\n\0line two", 18));
    std::string error;
    const auto text = UntrustedFile::readText(p, kTestKind, error);
    ASSERT_TRUE(text) << error;
    EXPECT_EQ(*text, std::string("line one\n\0line two", 18));
    const auto bytes = UntrustedFile::readBytes(p, kTestKind, error);
    ASSERT_TRUE(bytes) << error;
    EXPECT_EQ(bytes->size(), 18u);
    EXPECT_EQ((*bytes)[9], 0);
    // Empty is a regular file too.
    const auto empty = UntrustedFile::readText(write("e.txt", ""), kTestKind, error);
    ASSERT_TRUE(empty) << error;
    EXPECT_TRUE(empty->empty());
}

TEST_F(UntrustedFileTest, AMissingFileSaysSoWithItsKind) {
    std::string error;
    EXPECT_FALSE(UntrustedFile::readText(m_dir / "absent.toml", kTestKind, error));
    EXPECT_EQ(error, "open(" + (m_dir / "absent.toml").string() + "): No such file or directory (test file)");
}

TEST_F(UntrustedFileTest, AFifoIsRefusedAtOnceWithoutWaitingForAWriter) {
    const auto p = m_dir / "fifo";
    ASSERT_EQ(::mkfifo(p.c_str(), 0600), 0);
    // A blocking open() would wait here for ever: no process ever opens the FIFO for writing.
    const UntrustedFile f = UntrustedFile::open(p, kTestKind);
    EXPECT_FALSE(f.ok());
    EXPECT_EQ(f.error(), p.string() + ": is a FIFO, not a regular file (test file)");
}

TEST_F(UntrustedFileTest, DevicesAndDirectoriesAreRefusedNamed) {
    std::string error;
    EXPECT_FALSE(UntrustedFile::readText("/dev/zero", kTestKind, error));
    EXPECT_EQ(error, "/dev/zero: is a character device, not a regular file (test file)");
    EXPECT_FALSE(UntrustedFile::readBytes("/dev/null", kTestKind, error));
    EXPECT_EQ(error, "/dev/null: is a character device, not a regular file (test file)");
    EXPECT_FALSE(UntrustedFile::readText(m_dir, kTestKind, error));
    EXPECT_EQ(error, m_dir.string() + ": is a directory, not a regular file (test file)");
    // A kind without a cap (a streamed file) refuses them all the same.
    EXPECT_FALSE(UntrustedFile::open("/dev/zero", FileKind{"log", 0}).ok());
}

TEST_F(UntrustedFileTest, TheCapIsCheckedOnTheSizeBeforeAnythingIsRead) {
    // Sparse files: one of 64 GiB costs no disk and, refused on its size, no memory.
    for (const std::uint64_t size : {std::uint64_t{101}, std::uint64_t{4096}, std::uint64_t{64} << 30}) {
        const auto p = write("big", "");
        ASSERT_EQ(::truncate(p.c_str(), static_cast<off_t>(size)), 0);
        std::string error;
        EXPECT_FALSE(UntrustedFile::readBytes(p, kTestKind, error)) << size;
        EXPECT_EQ(error, p.string() + ": " + std::to_string(size) + " bytes, over the limit of 100 bytes (test file)");
    }
    // At the cap exactly: read.
    const auto p = write("full", std::string(100, 'x'));
    std::string error;
    const auto bytes = UntrustedFile::readBytes(p, kTestKind, error);
    ASSERT_TRUE(bytes) << error;
    EXPECT_EQ(bytes->size(), 100u);
    // The limit is said in whole units where it has them.
    const auto q = write("mib", "");
    ASSERT_EQ(::truncate(q.c_str(), (4 << 20) + 1), 0);
    EXPECT_EQ(UntrustedFile::open(q, FileKind{"config file", 4 << 20}).error(),
              q.string() + ": 4194305 bytes, over the limit of 4 MiB (config file)");
}

TEST_F(UntrustedFileTest, AFileThatGrowsWhileOpenIsReadNoFurtherThanTheCap) {
    const auto p = write("grows", "0123456789");
    UntrustedFile f = UntrustedFile::open(p, kTestKind);
    ASSERT_TRUE(f.ok()) << f.error();
    EXPECT_EQ(f.size(), 10u);
    std::ofstream(p, std::ios::binary | std::ios::app) << std::string(1000, 'y');
    std::string text;
    EXPECT_FALSE(f.readAll(text));
    EXPECT_TRUE(text.empty());
    EXPECT_EQ(f.error(), p.string() + ": grew past the limit of 100 bytes while being read (test file)");

    // Growth within the cap is read; a file that shrank gives what is left.
    const auto q = write("small", "0123456789");
    UntrustedFile g = UntrustedFile::open(q, kTestKind);
    std::ofstream(q, std::ios::binary | std::ios::app) << std::string(50, 'z');
    ASSERT_TRUE(g.readAll(text)) << g.error();
    EXPECT_EQ(text.size(), 60u);
    UntrustedFile h = UntrustedFile::open(q, kTestKind);
    ASSERT_EQ(::truncate(q.c_str(), 5), 0);
    ASSERT_TRUE(h.readAll(text)) << h.error();
    EXPECT_EQ(text, "01234");
}

TEST_F(UntrustedFileTest, AKindWithoutACapReadsAsLongAsTheFileIs) {
    const auto p = write("log", std::string(10000, 'l'));
    UntrustedFile f = UntrustedFile::open(p, FileKind{"candump log", 0});
    ASSERT_TRUE(f.ok()) << f.error();
    std::ofstream(p, std::ios::binary | std::ios::app) << std::string(20000, 'm');
    std::vector<std::uint8_t> bytes;
    ASSERT_TRUE(f.readAll(bytes)) << f.error();
    EXPECT_EQ(bytes.size(), 30000u);
    // The descriptor can be handed over; the file is then no longer open.
    UntrustedFile g = UntrustedFile::open(p, FileKind{"candump log", 0});
    const int fd = g.release();
    EXPECT_GE(fd, 0);
    EXPECT_FALSE(g.ok());
    EXPECT_EQ(::close(fd), 0);
}

}  // namespace
