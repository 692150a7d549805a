// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "navmap/ipc/can/candump_reader.h"
#include "test_paths.h"

using navmap::ipc::CandumpReader;
using navmap::ipc::CandumpRecord;
using navmap::ipc::CanFrame;

namespace {

CanFrame parseOk(std::string_view line) {
    auto r = CandumpReader::parseLine(line);
    EXPECT_TRUE(r.ok()) << line << ": " << (r.ok() ? "" : r.error().message);
    return r.ok() ? r.value().frame : CanFrame{};
}

std::string parseError(std::string_view line) {
    auto r = CandumpReader::parseLine(line);
    EXPECT_FALSE(r.ok()) << line;
    return r.ok() ? std::string() : r.error().message;
}

}  // namespace

TEST(CandumpReader, ClassicFrameWithMicrosecondTimestamp) {
    auto r = CandumpReader::parseLine("(1487342025.615950) can0 187#E21408C800100300");
    ASSERT_TRUE(r.ok());
    const CanFrame& f = r.value().frame;
    EXPECT_EQ(r.value().interface_name, "can0");
    EXPECT_EQ(f.id, 0x187U);
    EXPECT_FALSE(f.extended());
    EXPECT_FALSE(f.fd());
    EXPECT_EQ(f.len, 8);
    EXPECT_EQ(f.data[0], 0xE2);
    EXPECT_EQ(f.data[7], 0x00);
    EXPECT_EQ(f.timestamp.time_since_epoch().count(), 1487342025615950000LL);
}

TEST(CandumpReader, TwoDecimalTimestampLowercaseHex) {
    const CanFrame f = parseOk("(1484869955.91) can1 091#7ef47ef424f1f000");
    EXPECT_EQ(f.id, 0x91U);
    EXPECT_EQ(f.data[1], 0xF4);
    EXPECT_EQ(f.timestamp.time_since_epoch().count(), 1484869955910000000LL);
    EXPECT_EQ(parseOk("(5) vcan0 123#").timestamp.time_since_epoch().count(), 5000000000LL);
    EXPECT_EQ(parseOk("(1.123456789123) vcan0 123#").timestamp.time_since_epoch().count(), 1123456789LL);
}

TEST(CandumpReader, ExtendedRemoteFdAndErrorFrames) {
    CanFrame f = parseOk("(1.0) can0 1ABCDEF0#0102");
    EXPECT_TRUE(f.extended());
    EXPECT_EQ(f.id, 0x1ABCDEF0U);
    EXPECT_EQ(f.len, 2);
    EXPECT_EQ(f.key(), 0x9ABCDEF0U);

    f = parseOk("(1.0) can0 123#R");
    EXPECT_TRUE(f.rtr());
    EXPECT_EQ(f.len, 0);
    f = parseOk("(1.0) can0 123#R5");
    EXPECT_TRUE(f.rtr());
    EXPECT_EQ(f.len, 5);

    f = parseOk("(1.0) can0 123##3112233445566778899AABBCC");
    EXPECT_TRUE(f.fd());
    EXPECT_EQ(f.len, 12);
    EXPECT_EQ(f.flags & navmap::ipc::kCanBrs, navmap::ipc::kCanBrs);
    EXPECT_EQ(f.flags & navmap::ipc::kCanEsi, navmap::ipc::kCanEsi);
    EXPECT_EQ(f.data[11], 0xCC);
    std::string big = "(1.0) can0 12345678##0";
    for (int i = 0; i < 64; ++i) {
        big += "A5";
    }
    f = parseOk(big);
    EXPECT_EQ(f.len, 64);
    EXPECT_TRUE(f.extended());

    f = parseOk("(1.0) can0 20000040#0000000000000000");  // CAN_ERR_FLAG | CAN_ERR_BUSOFF
    EXPECT_TRUE(f.error());
    EXPECT_FALSE(f.extended());
    EXPECT_EQ(f.id, 0x40U);

    f = parseOk("(1.0) can0 123#11.22.33");
    EXPECT_EQ(f.len, 3);
    EXPECT_EQ(f.data[2], 0x33);
    f = parseOk("(1.0) can0 123#1122334455667788_C");  // len8_dlc
    EXPECT_EQ(f.len, 8);
    f = parseOk("(1.0) can0 123#00 R");  // direction flag of newer candump
    EXPECT_EQ(f.len, 1);
    f = parseOk("(1.0) can0 123#00\r");
    EXPECT_EQ(f.len, 1);
}

TEST(CandumpReader, TimestampsUpToTheEndOfCanTime) {
    // CanTime is int64 nanoseconds: 9223372035.999999999 s is the last timestamp that fits.
    auto r = CandumpReader::parseLine("(9223372035.999999999) can0 123#00");
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().frame.timestamp.time_since_epoch().count(), 9223372035999999999LL);
    EXPECT_EQ(parseError("(9618394400.000000) can0 6A0#00"),
              "timestamp 9618394400 s is out of range (0 to 9223372035 s)");
}

TEST(CandumpReader, FormatRoundTrip) {
    for (const char* text :
         {"123#DEADBEEF", "1ABCDEF0#R", "123#R4", "123##1AABB", "7FF#", "20000004#0004000000000000"}) {
        const CanFrame f = parseOk(std::string("(0.0) can0 ") + text);
        EXPECT_EQ(navmap::ipc::formatCandumpPayload(f), text);
    }
}

TEST(CandumpReader, MalformedLinesSayWhy) {
    EXPECT_NE(parseError("(1487342025.615950) can0").find("truncated"), std::string::npos);
    EXPECT_NE(parseError("(1487342025.6159").find("not closed"), std::string::npos);
    EXPECT_NE(parseError("1487342025.615950 can0 123#00").find("expected '('"), std::string::npos);
    EXPECT_NE(parseError("(abc) can0 123#00").find("bad timestamp"), std::string::npos);
    EXPECT_NE(parseError("(1.) can0 123#00").find("no digits after"), std::string::npos);
    EXPECT_NE(parseError("(1.0)can0 123#00").find("blank"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123").find("no '#'"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 12#00").find("3 (11-bit) or 8 (29-bit)"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 1234#00").find("3 (11-bit) or 8 (29-bit)"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 80G#00").find("not hex"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 800#00").find("out of range (max 0x7FF)"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 40000000#00").find("out of range (max 0x1FFFFFFF)"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#0G").find("not hex"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#123").find("odd number"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#112233445566778899").find("more than 8"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123##0112233445566778899").find("not a valid FD length"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123##").find("flags nibble"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123##X00").find("flags"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123###00").find("XL"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#R9").find("0..8"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#RX").find("0..8"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#1122_C").find("len8_dlc"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 20000040#00").find("8 data bytes"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 123#00 extra").find("after the frame"), std::string::npos);
    EXPECT_NE(parseError("(1.0) averyveryverylongname 123#00").find("1..15"), std::string::npos);
    EXPECT_NE(parseError(std::string(600, 'x')).find("longer than 512"), std::string::npos);
    EXPECT_NE(parseError("(1.0) can0 \xff\xfe#00").find("3 (11-bit)"), std::string::npos);
    EXPECT_NE(parseError("(1.0) ca\x01n0 123#00").find("non-printable"), std::string::npos);
}

TEST(CandumpReader, CountsAndLineNumbersAndContinuesAfterBadLines) {
    std::istringstream in(
        "(1.000000) can0 100#01\n"
        "\n"
        "(1.000100) can0 1#01\n"  // line 3: bad id length
        "# a comment\n"
        "(1.000200) can1 101##100112233\n"  // line 5: not a valid FD length (4 is fine) -> ok
        "(1.000300) can0 102#R\n"
        "garbage \xff\xfe\n"  // line 7
        "(1.000400) can0 20000004#0004000000000000\n"
        "(1.000500) can0 103#0011");
    CandumpReader reader("test.log");
    const auto records = reader.readAll(in);
    ASSERT_EQ(records.size(), 5U);
    const auto& c = reader.counters();
    EXPECT_EQ(c.lines, 9U);
    EXPECT_EQ(c.frames, 5U);
    EXPECT_EQ(c.malformed, 2U);
    EXPECT_EQ(c.skipped, 2U);
    EXPECT_EQ(c.fd_frames, 1U);
    EXPECT_EQ(c.remote_frames, 1U);
    EXPECT_EQ(c.error_frames, 1U);
    ASSERT_EQ(reader.errors().size(), 2U);
    EXPECT_EQ(reader.errors()[0].line, 3U);
    EXPECT_EQ(reader.errors()[0].message.rfind("test.log:3: CAN id '1'", 0), 0U) << reader.errors()[0].message;
    EXPECT_EQ(reader.errors()[1].line, 7U);
    ASSERT_EQ(reader.interfaces().size(), 2U);
    EXPECT_EQ(reader.interfaces()[records[1].interface_index], "can1");
    EXPECT_EQ(records.back().frame.id, 0x103U);
}

TEST(CandumpReader, ErrorListIsBoundedButCountIsNot) {
    std::string text;
    for (int i = 0; i < 1000; ++i) {
        text += "bad line\n";
    }
    std::istringstream in(text);
    CandumpReader reader;
    EXPECT_TRUE(reader.readAll(in).empty());
    EXPECT_EQ(reader.counters().malformed, 1000U);
    EXPECT_EQ(reader.errors().size(), CandumpReader::kMaxErrors);
}

TEST(CandumpReader, MissingFile) {
    auto r = navmap::ipc::loadCandumpFile("/nonexistent.candump");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "open(/nonexistent.candump): cannot read candump file");
}

TEST(CandumpReader, RealFordLogsLoadCompletely) {
    const auto dir = navmap::test::ipcDataDir() / "can";
    struct Expect {
        const char* name;
        std::size_t frames;
        const char* iface;
    };
    // Frame counts from tests/ipc/data/SOURCES.md.
    const Expect logs[] = {
        {"ford_fusion_2017_acc_on_going_at_50km_per_hour.candump", 10669, "can0"},
        {"ford_fusion_2017_lane_keep_assist_on_red_lines.candump", 2841, "vcan0"},
        {"ford_fusion_2017_lkas-long.candump", 46332, nullptr},
    };
    for (const auto& e : logs) {
        auto r = navmap::ipc::loadCandumpFile(dir / e.name);
        ASSERT_TRUE(r.ok()) << r.error().message;
        const auto& log = r.value();
        EXPECT_EQ(log.counters.frames, e.frames) << e.name;
        EXPECT_EQ(log.counters.malformed, 0U) << e.name;
        if (e.iface != nullptr) {
            ASSERT_EQ(log.interfaces.size(), 1U);
            EXPECT_EQ(log.interfaces[0], e.iface);
        } else {
            // lkas-long: can1 45,350 frames and can0 982.
            EXPECT_EQ(log.frames("can1").size(), 45350U);
            EXPECT_EQ(log.frames("can0").size(), 982U);
        }
        for (const auto& rec : log.records) {
            ASSERT_EQ(rec.frame.len, 8);
            ASSERT_FALSE(rec.frame.extended());
        }
    }
}

TEST(CandumpReader, TimestampsBeyondTheClockAreMalformedLinesNotOverflows) {
    // 16183940000 s (a digit too many) overflowed the nanosecond clock: undefined behaviour.
    EXPECT_EQ(parseError("(16183940000.000000) can0 123#00"),
              "timestamp 16183940000 s is out of range (0 to 9223372035 s)");
    EXPECT_EQ(parseError("(9223372036.0) can0 123#00"), "timestamp 9223372036 s is out of range (0 to 9223372035 s)");
    EXPECT_EQ(parseError("(18446744073709551615.0) can0 123#00"),
              "timestamp 18446744073709551615 s is out of range (0 to 9223372035 s)");
    EXPECT_EQ(parseError("(99999999999999999999999.9) can0 123#00"),
              "timestamp 99999999999999999999999 s is out of range (0 to 9223372035 s)");
    EXPECT_NE(parseError("(-1.0) can0 123#00").find("bad timestamp seconds"), std::string::npos);
    // The last representable second, to the nanosecond.
    auto last = CandumpReader::parseLine("(9223372035.999999999) can0 123#00");
    ASSERT_TRUE(last.ok()) << last.error().message;
    EXPECT_EQ(last.value().frame.timestamp.time_since_epoch().count(), 9223372035999999999LL);
    // In a log: counted with its line number, reading goes on.
    std::istringstream in("(16183940000.000000) can0 123#00\n(1618394000.000000) can0 123#01\n");
    CandumpReader reader("t.log");
    const auto records = reader.readAll(in);
    ASSERT_EQ(records.size(), 1U);
    EXPECT_EQ(records[0].frame.data[0], 1U);
    EXPECT_EQ(reader.counters().malformed, 1U);
    ASSERT_EQ(reader.errors().size(), 1U);
    EXPECT_EQ(reader.errors()[0].message, "t.log:1: timestamp 16183940000 s is out of range (0 to 9223372035 s)");
}

TEST(CandumpReader, BinaryDataIsRefusedAtItsFirstControlByte) {
    std::istringstream in(std::string("(1.0) can0 123#00\n") + std::string(1000, '\0'));
    CandumpReader reader("zeros.log");
    const auto records = reader.readAll(in);
    EXPECT_EQ(records.size(), 1U);
    EXPECT_EQ(reader.failure(), "zeros.log: byte 0x00 at offset 18 (line 2): binary data, not a candump log");
    // Once refused, further bytes are refused too.
    EXPECT_FALSE(reader.feedBytes("(2.0) can0 123#00\n", [](const auto&) {}).ok());
    const std::string fails[] = {std::string("\x7f", 1), "\x1b[31m", std::string("(1.0) can0 123#00\x03\n")};
    for (const auto& bytes : fails) {
        CandumpReader r;
        EXPECT_FALSE(r.feedBytes(bytes, [](const auto&) {}).ok());
        EXPECT_NE(r.failure().find("binary data, not a candump log"), std::string::npos) << r.failure();
    }
    // Tabs, CR and UTF-8 in comments are text.
    CandumpReader text;
    std::size_t frames = 0;
    EXPECT_TRUE(text.feedBytes("# caf\xc3\xa9\r\n(1.0)\tcan0\t123#00\r\n", [&](const auto&) { ++frames; }).ok());
    EXPECT_EQ(frames, 1U);
}

TEST(CandumpReader, OverlongLinesAreCountedAndSkippedInABoundedBuffer) {
    CandumpReader reader("long.log");
    std::vector<std::uint32_t> ids;
    const auto sink = [&](const navmap::ipc::CandumpRecord& r) { ids.push_back(r.frame.id); };
    std::size_t most = 0;
    // A 200 kB line in 1 kB chunks, ended; then a good line split across chunks.
    const std::string chunk(1000, 'A');
    for (int i = 0; i < 60; ++i) {
        ASSERT_TRUE(reader.feedBytes(chunk, sink).ok());
        most = std::max(most, reader.bufferedBytes());
    }
    ASSERT_TRUE(reader.feedBytes("\n(1.0) can0 1", sink).ok());
    ASSERT_TRUE(reader.feedBytes("23#00\n", sink).ok());
    EXPECT_LE(most, CandumpReader::kMaxLineLength + 1);
    EXPECT_EQ(ids, std::vector<std::uint32_t>{0x123});
    EXPECT_EQ(reader.counters().malformed, 1U);
    EXPECT_EQ(reader.errors().at(0).message, "long.log:1: line is longer than 512 characters");
    // A line that never ends is no log: refused after kMaxSkipBytes, not read forever.
    for (int i = 0; i < 70 && reader.failure().empty(); ++i) {
        (void)reader.feedBytes(chunk, sink);
    }
    EXPECT_EQ(reader.failure(), "long.log:3: no end of line in 65536 bytes, not a candump log");
    // The last line without a newline still counts.
    CandumpReader tail;
    ASSERT_TRUE(tail.feedBytes("(1.0) can0 123#00\n(2.0) can0 124#00", sink).ok());
    tail.finishBytes(sink);
    EXPECT_EQ(ids.back(), 0x124U);
    EXPECT_EQ(tail.counters().frames, 2U);
}
