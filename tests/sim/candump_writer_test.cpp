// SPDX-License-Identifier: Apache-2.0
// CandumpWriter: exact candump -l lines, read back by ipc::CandumpReader, atomic publish.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "navmap/ipc/can/candump_reader.h"
#include "navmap/sim/candump_writer.h"

namespace navmap::sim {
namespace {

std::filesystem::path tempPath(const std::string& name) {
    return std::filesystem::temp_directory_path() / ("navmap_sim_" + std::to_string(::getpid()) + "_" + name);
}

ipc::CanFrame frame(std::uint32_t id, std::initializer_list<std::uint8_t> bytes, std::int64_t us) {
    ipc::CanFrame f;
    f.id = id;
    f.len = static_cast<std::uint8_t>(bytes.size());
    std::copy(bytes.begin(), bytes.end(), f.data.begin());
    f.timestamp = ipc::CanTime(std::chrono::microseconds(us));
    return f;
}

TEST(CandumpWriter, FormatsExactlyLikeCandump) {
    EXPECT_EQ(
        formatCandumpLine(frame(0x6A0, {0x3B, 0x20, 0x56, 0x19, 0xC4, 0x31, 0xE8, 0x00}, 1618394400000000), "can0"),
        "(1618394400.000000) can0 6A0#3B205619C431E800");
    EXPECT_EQ(formatCandumpLine(frame(0x1, {0xAB}, 1618394400123456), "vcan0"), "(1618394400.123456) vcan0 001#AB");
    EXPECT_EQ(formatCandumpLine(frame(0x6A2, {}, 5), "can1"), "(0.000005) can1 6A2#");
    ipc::CanFrame ext = frame(0x1ABCDEF0, {1, 2}, 2000000);
    ext.flags = ipc::kCanExtended;
    EXPECT_EQ(formatCandumpLine(ext, "can0"), "(2.000000) can0 1ABCDEF0#0102");
}

TEST(CandumpWriter, WritesALogTheReaderAcceptsWithoutErrors) {
    const auto path = tempPath("rt.candump");
    std::vector<ipc::CanFrame> frames;
    frames.reserve(100);
    for (int i = 0; i < 100; ++i) {
        frames.push_back(frame(0x6A0 + static_cast<std::uint32_t>(i % 3),
                               {static_cast<std::uint8_t>(i), 0, 0xFF, 1, 2, 3, 4, static_cast<std::uint8_t>(255 - i)},
                               1618394400000000 + i * 20000));
    }
    {
        auto w = CandumpWriter::open(path, "can0");
        ASSERT_TRUE(w.ok()) << w.error().message;
        for (const auto& f : frames) ASSERT_TRUE(w.value().write(f).ok());
        EXPECT_FALSE(std::filesystem::exists(path));  // published only by close()
        ASSERT_TRUE(w.value().close().ok());
        EXPECT_EQ(w.value().lines(), 100U);
    }
    auto log = ipc::loadCandumpFile(path);
    ASSERT_TRUE(log.ok()) << log.error().message;
    EXPECT_EQ(log.value().counters.malformed, 0U);
    ASSERT_EQ(log.value().records.size(), frames.size());
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const auto& got = log.value().records[i].frame;
        EXPECT_EQ(got.id, frames[i].id);
        EXPECT_EQ(got.len, frames[i].len);
        EXPECT_EQ(got.data, frames[i].data);
        EXPECT_EQ(got.timestamp, frames[i].timestamp);
    }
    EXPECT_EQ(log.value().interfaces, std::vector<std::string>{"can0"});
    std::filesystem::remove(path);
}

TEST(CandumpWriter, UnclosedLogIsNotPublished) {
    const auto path = tempPath("abandoned.candump");
    {
        auto w = CandumpWriter::open(path, "can0");
        ASSERT_TRUE(w.ok());
        ASSERT_TRUE(w.value().write(frame(0x6A0, {1}, 0)).ok());
    }
    EXPECT_FALSE(std::filesystem::exists(path));
    EXPECT_FALSE(std::filesystem::exists(path.string() + ".tmp"));
}

TEST(CandumpWriter, ErrorsNameTheCallAndTheFile) {
    auto w = CandumpWriter::open("/nonexistent-dir/x.candump", "can0");
    ASSERT_FALSE(w.ok());
    EXPECT_EQ(w.error().message, "fopen(/nonexistent-dir/x.candump.tmp): No such file or directory");
    auto bad = CandumpWriter::open(tempPath("x.candump"), "can 0");
    ASSERT_FALSE(bad.ok());
    EXPECT_NE(bad.error().message.find("interface name"), std::string::npos);
}

}  // namespace
}  // namespace navmap::sim
