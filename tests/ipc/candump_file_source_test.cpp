// SPDX-License-Identifier: Apache-2.0
// CandumpFileSource: candump files streamed into the Replayer in bounded memory. /dev/zero and
// other non-logs are refused at once; a large log plays without its size showing in memory;
// looping rewinds the file.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "navmap/ipc/can/candump_file_source.h"
#include "navmap/ipc/can/replayer.h"

using namespace std::chrono_literals;
using navmap::ipc::CandumpFileSource;
using navmap::ipc::CandumpReader;
using navmap::ipc::CanFrame;
using navmap::ipc::CanTime;
using navmap::ipc::Replayer;
using navmap::ipc::ReplayOptions;

namespace {

namespace fs = std::filesystem;

// VmRSS of this process, bytes.
std::size_t rssBytes() {
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return 0;
    char line[256];
    unsigned long long kb = 0;
    while (std::fgets(line, sizeof line, f)) {
        if (std::sscanf(line, "VmRSS: %llu kB", &kb) == 1) break;
    }
    std::fclose(f);
    return static_cast<std::size_t>(kb) * 1024;
}

struct TempFile {
    fs::path path;
    explicit TempFile(const std::string& name)
        : path(fs::temp_directory_path() / (name + "-" + std::to_string(::getpid()))) {}
    ~TempFile() { fs::remove(path); }
};

std::unique_ptr<Replayer> replay(const fs::path& path, ReplayOptions options, const CandumpFileSource** source) {
    auto s = CandumpFileSource::open(path);
    EXPECT_TRUE(s.ok()) << (s.ok() ? "" : s.error().message);
    if (!s.ok()) return nullptr;
    *source = s.value().get();
    return std::make_unique<Replayer>(std::move(s).value(), options);
}

const CanTime kT0 = CanTime(std::chrono::seconds(5000));

}  // namespace

TEST(CandumpFileSource, BinaryZerosAreRefusedAtOnceInBoundedMemory) {
    // readAll() into memory reached 3.3 GB in 6 s on /dev/zero (one endless "line"). /dev/zero
    // itself is refused at open now (no regular file, below); 64 MiB of zeros in a regular
    // (sparse) file are refused on their first chunk.
    TempFile zeros("navmap-zeros-candump");
    std::ofstream(zeros.path).close();
    ASSERT_EQ(::truncate(zeros.path.c_str(), off_t{64} << 20), 0);
    const std::size_t rss0 = rssBytes();
    const auto t0 = std::chrono::steady_clock::now();
    const CandumpFileSource* source = nullptr;
    auto r = replay(zeros.path, ReplayOptions{}, &source);
    ASSERT_TRUE(r);
    const auto elapsed = std::chrono::steady_clock::now() - t0;
    EXPECT_TRUE(r->finished());
    EXPECT_EQ(r->error(), zeros.path.string() + ": byte 0x00 at offset 0 (line 1): binary data, not a candump log");
    EXPECT_EQ(r->emitted(), 0U);
    EXPECT_LE(source->bytesRead(), CandumpFileSource::kChunkBytes);
    EXPECT_LT(elapsed, 1s);
    EXPECT_LT(rssBytes(), rss0 + (std::size_t{4} << 20));
    // Resetting tries again and fails the same way (the source is never half-trusted).
    r->reset(kT0);
    EXPECT_TRUE(r->finished());
    EXPECT_NE(r->error().find("binary data"), std::string::npos);
}

TEST(CandumpFileSource, ALargeLogPlaysInBoundedMemory) {
    // 24 MB of log: about 700000 frames, 67 MB as CandumpRecords in memory.
    TempFile log("navmap-large-candump");
    {
        std::FILE* f = std::fopen(log.path.c_str(), "w");
        ASSERT_NE(f, nullptr);
        for (int i = 0; i < 700000; ++i) {
            std::fprintf(f, "(%d.%06d) can0 %03X#%016X\n", 1600000000 + i / 1000, (i % 1000) * 1000, 0x100 + i % 0x600,
                         i);
        }
        std::fclose(f);
    }
    ASSERT_GT(fs::file_size(log.path), std::uintmax_t{20} << 20);
    const std::size_t rss0 = rssBytes();
    ReplayOptions o;
    o.speed = 0.0;  // as fast as possible
    const CandumpFileSource* source = nullptr;
    auto r = replay(log.path, o, &source);
    ASSERT_TRUE(r);
    r->reset(kT0);
    std::size_t n = 0, most = 0, rss_most = 0;
    std::uint32_t last_data = 0;
    bool in_order = true;
    const auto sink = [&](const CanFrame& f) {
        const std::uint32_t v = (std::uint32_t{f.data[4]} << 24) | (std::uint32_t{f.data[5]} << 16) |
                                (std::uint32_t{f.data[6]} << 8) | f.data[7];
        in_order = in_order && (n == 0 || v == last_data + 1);
        last_data = v;
        ++n;
    };
    while (!r->finished()) {
        r->advanceTo(kT0, sink, 10000);
        most = std::max(most, source->bufferedBytes());
        rss_most = std::max(rss_most, rssBytes());
    }
    EXPECT_EQ(r->error(), "");
    EXPECT_EQ(n, 700000U);
    EXPECT_TRUE(in_order);
    EXPECT_EQ(source->reader().counters().frames, 700000U);
    // The chunk, one line and the frames of one chunk (at least 40 bytes a line here).
    EXPECT_LE(most, CandumpFileSource::kChunkBytes + CandumpReader::kMaxLineLength + 1 +
                        CandumpFileSource::kChunkBytes / 40 * sizeof(navmap::ipc::CandumpRecord));
    EXPECT_LT(rss_most, rss0 + (std::size_t{8} << 20)) << "RSS grew by " << (rss_most - rss0) / 1024 << " KiB";
}

TEST(CandumpFileSource, LoopingRewindsTheFileAndBadLinesAreCounted) {
    TempFile log("navmap-loop-candump");
    std::ofstream(log.path) << "(100.000) can0 001#01\n"
                               "(100.010) can0 002#02\n"
                               "(16183940000.000000) can0 003#03\n" +
                                   std::string(600, 'x') +
                                   "\n"
                                   "(100.020) can0 004#04\n";
    ReplayOptions o;
    o.loop = true;
    const CandumpFileSource* source = nullptr;
    auto r = replay(log.path, o, &source);
    ASSERT_TRUE(r);
    r->reset(kT0);
    std::vector<std::uint32_t> ids;
    const auto sink = [&](const CanFrame& f) { ids.push_back(f.id); };
    r->advanceTo(kT0 + 95ms, sink);  // a loop lasts 20 + 10 ms: 0 10 20 | 30 40 50 | 60 70 80 | 90
    EXPECT_EQ(ids, (std::vector<std::uint32_t>{1, 2, 4, 1, 2, 4, 1, 2, 4, 1}));
    EXPECT_EQ(r->loops(), 3U);
    EXPECT_FALSE(r->finished());
    // Two bad lines a pass, each pass counted; line numbers restart with the file.
    EXPECT_EQ(source->reader().counters().malformed, 8U);
    ASSERT_GE(source->reader().errors().size(), 4U);
    const std::string name = log.path.string();
    EXPECT_EQ(source->reader().errors()[0].message,
              name + ":3: timestamp 16183940000 s is out of range (0 to 9223372035 s)");
    EXPECT_EQ(source->reader().errors()[1].message, name + ":4: line is longer than 512 characters");
    EXPECT_EQ(source->reader().errors()[2].message, source->reader().errors()[0].message);
}

TEST(CandumpFileSource, TextThatIsNoLogIsRefusedQuickly) {
    TempFile log("navmap-text-candump");
    {
        std::ofstream out(log.path);
        for (int i = 0; i < 100000; ++i) out << "This is a novel, not a CAN log. Line " << i << "\n";
    }
    const CandumpFileSource* source = nullptr;
    auto r = replay(log.path, ReplayOptions{}, &source);
    ASSERT_TRUE(r);
    EXPECT_TRUE(r->finished());
    EXPECT_EQ(r->error(),
              log.path.string() + ": not a candump log: the first " +
                  std::to_string(source->reader().counters().malformed) +
                  " lines are malformed (first: " + log.path.string() +
                  ":1: expected '(' and a timestamp at the start, got 'This is a novel, not a CAN log. ...')");
    EXPECT_GE(source->reader().counters().malformed, CandumpFileSource::kMaxLeadingMalformed);
    EXPECT_LT(source->reader().counters().lines, 2000U) << "refused within its first lines";
    // An empty log is no error: there is just nothing to play.
    std::ofstream(log.path, std::ios::trunc) << "# nothing\n";
    auto empty = replay(log.path, ReplayOptions{}, &source);
    EXPECT_TRUE(empty->finished());
    EXPECT_EQ(empty->error(), "");
    auto missing = CandumpFileSource::open("/nonexistent/drive.candump");
    ASSERT_FALSE(missing.ok());
    EXPECT_EQ(missing.error().message, "open(/nonexistent/drive.candump): No such file or directory (candump log)");
}

// A log that is no regular file is refused at once: a FIFO used to block navmapd's start-up (and
// SIGTERM) until a writer came, /dev/zero to be replayed as binary data.
TEST(CandumpFileSource, AFifoOrADeviceIsRefusedWithoutWaiting) {
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-candump-fifo-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto fifo = dir / "drive.candump";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto r = CandumpFileSource::open(fifo);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, fifo.string() + ": is a FIFO, not a regular file (candump log)");
    r = CandumpFileSource::open("/dev/zero");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "/dev/zero: is a character device, not a regular file (candump log)");
    std::filesystem::remove_all(dir);
}
