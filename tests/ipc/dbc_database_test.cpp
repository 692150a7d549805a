// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "navmap/ipc/can/dbc_database.h"
#include "test_paths.h"

using navmap::ipc::ByteOrder;
using navmap::ipc::DbcDatabase;
using navmap::ipc::MuxRole;

namespace {

constexpr const char* kSmallDbc = R"(VERSION ""

NS_ :
    CM_
    BA_DEF_
    VAL_

BS_:

BU_: ECU1 ECU2

BO_ 256 Engine: 8 ECU1
 SG_ Rpm : 7|16@0+ (0.25,0) [0|16383.75] "rpm" ECU2
 SG_ Temp : 16|8@1- (1,-40) [-40|215] "degC"  ECU2,ECU1

BO_ 2147484672 ExtMsg: 16 ECU2
 SG_ Mode M : 0|4@1+ (1,0) [0|15] "" ECU1
 SG_ A m0 : 8|16@1+ (0.1,0) [0|100] "%" ECU1
 SG_ B m1 : 8|16@1- (1,0) [0|0] "" ECU1
 SG_ F : 64|32@1- (1,0) [0|0] "" ECU1

CM_ SG_ 256 Rpm "A comment with BO_ 999 Fake: 8 X inside;
and a second line SG_ Bogus : 0|8@1+ (1,0) [0|0] "" X
that ends here";
BA_DEF_ SG_  "GenSigStartValue" INT 0 10000;
VAL_ 256 Temp 0 "Cold" 100 "Hot" ;
SIG_VALTYPE_ 2147484672 F : 1;
)";

}  // namespace

TEST(DbcDatabase, ParsesMessagesSignalsMultiplexingAndSkipsTheRest) {
    auto r = DbcDatabase::parse(kSmallDbc, "small.dbc", DbcDatabase::Mode::Strict);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const DbcDatabase& db = r.value();
    ASSERT_EQ(db.messages().size(), 2U);
    EXPECT_EQ(db.diagnosticCount(), 0U);

    const auto* engine = db.findMessage(256U);
    ASSERT_NE(engine, nullptr);
    EXPECT_EQ(engine->name, "Engine");
    EXPECT_EQ(engine->transmitter, "ECU1");
    ASSERT_EQ(engine->signals.size(), 2U);
    const auto& rpm = engine->signals[0];
    EXPECT_EQ(rpm.byte_order, ByteOrder::Motorola);
    EXPECT_EQ(rpm.start_bit, 7);
    EXPECT_EQ(rpm.length, 16);
    EXPECT_DOUBLE_EQ(rpm.factor, 0.25);
    EXPECT_DOUBLE_EQ(rpm.maximum, 16383.75);
    EXPECT_EQ(rpm.unit, "rpm");
    const auto& temp = engine->signals[1];
    EXPECT_EQ(temp.byte_order, ByteOrder::Intel);
    EXPECT_TRUE(temp.is_signed);
    EXPECT_DOUBLE_EQ(temp.offset, -40.0);
    EXPECT_EQ(temp.value_names.at(100), "Hot");
    EXPECT_EQ(temp.line, 14U);

    const auto* ext = db.findMessage(std::string_view("ExtMsg"));
    ASSERT_NE(ext, nullptr);
    EXPECT_TRUE(ext->extended);
    EXPECT_EQ(ext->id, 1024U);
    EXPECT_EQ(ext->key(), 0x80000400U);
    EXPECT_EQ(db.findMessage(0x80000400U), ext);
    EXPECT_EQ(db.findMessage(1024U), nullptr);  // the 11-bit id 0x400 is another frame
    EXPECT_EQ(ext->size, 16);
    EXPECT_EQ(ext->multiplexor, 0);
    EXPECT_EQ(ext->signals[1].mux_role, MuxRole::Multiplexed);
    EXPECT_EQ(ext->signals[2].mux_value, 1U);
    EXPECT_EQ(ext->signals[3].value_type, navmap::ipc::ValueType::Float32);
    // The comment text that looks like BO_/SG_ was not parsed.
    EXPECT_EQ(db.findMessage(999U), nullptr);
    EXPECT_EQ(engine->findSignal("Bogus"), nullptr);
}

TEST(DbcDatabase, MultiplexedDecodeAndEncode) {
    auto r = DbcDatabase::parse(kSmallDbc, "small.dbc");
    ASSERT_TRUE(r.ok());
    const auto* ext = r.value().findMessage(std::string_view("ExtMsg"));
    auto f0 = ext->encode({{"Mode", 0}, {"A", 42.5}, {"F", 2.25}});
    ASSERT_TRUE(f0.ok()) << f0.error().message;
    EXPECT_EQ(f0.value().len, 16);
    EXPECT_TRUE(f0.value().fd());
    EXPECT_TRUE(f0.value().extended());
    std::map<std::string, double> seen;
    ext->decodeAll(std::span(f0.value().data.data(), f0.value().len),
                   [&](const navmap::ipc::DbcSignal& s, double v) { seen[s.name] = v; });
    EXPECT_EQ(seen.size(), 3U);  // Mode, A, F; not B
    EXPECT_DOUBLE_EQ(seen["A"], 42.5);
    EXPECT_DOUBLE_EQ(seen["F"], 2.25);
    EXPECT_EQ(seen.count("B"), 0U);

    auto f1 = ext->encode({{"Mode", 1}, {"B", -5}});
    ASSERT_TRUE(f1.ok());
    seen.clear();
    ext->decodeAll(std::span(f1.value().data.data(), f1.value().len),
                   [&](const navmap::ipc::DbcSignal& s, double v) { seen[s.name] = v; });
    EXPECT_DOUBLE_EQ(seen["B"], -5.0);
    EXPECT_EQ(seen.count("A"), 0U);

    auto wrong_page = ext->encode({{"Mode", 1}, {"A", 1}});
    ASSERT_FALSE(wrong_page.ok());
    EXPECT_NE(wrong_page.error().message.find("needs multiplexor value 0"), std::string::npos);
    auto unknown = ext->encode({{"Nope", 1}});
    ASSERT_FALSE(unknown.ok());
    EXPECT_NE(unknown.error().message.find("no signal named 'Nope'"), std::string::npos);
}

struct BadDbcCase {
    const char* text;
    std::size_t line;
    const char* expected;
};

TEST(DbcDatabase, BrokenEntriesGiveLineNumberedErrors) {
    const BadDbcCase cases[] = {
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n SG_ T : 8|8@2+ (1,0) [0|1] \"\" X\n", 3,
         "byte order must be @0"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (1,0 [0|1] \"\" X\n", 2, "bad offset"},
        {"BO_ 100 M: 8 X\n SG_ S : 60|8@1+ (1,0) [0|1] \"\" X\n", 2, "need 9 bytes, message M has 8"},
        {"BO_ 100 M: 2 X\n SG_ S : 7|24@0+ (1,0) [0|1] \"\" X\n", 2, "need 3 bytes, message M has 2"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|0@1+ (1,0) [0|1] \"\" X\n", 2, "is not 1..64 bits"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|65@1+ (1,0) [0|1] \"\" X\n", 2, "is not 1..64 bits"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1* (1,0) [0|1] \"\" X\n", 2, "expected + (unsigned) or - (signed)"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"unterminated\n", 2, "unterminated quoted string"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (x,0) [0|1] \"\" X\n", 2, "bad factor"},
        {"BO_ 100 M: 8 X\n SG_ S\n", 2, "expected ':'"},
        {"BO_ 100 M: 8 X\n SG_ S q : 0|8@1+ (1,0) [0|1] \"\" X\n", 2, "bad multiplexer indicator 'q'"},
        {"BO_ 100 M: 8 X\n SG_ S m : 0|8@1+ (1,0) [0|1] \"\" X\n", 2, "bad multiplexer indicator 'm'"},
        {"BO_ 100 M: 8 X\n SG_ S m3 : 0|8@1+ (1,0) [0|1] \"\" X\n", 2, "has no multiplexor"},
        // Numbers: a multiplexer value that is not all digits or does not fit 32 bits, a sign
        // without its number, an id past 64 bits.
        {"BO_ 100 M: 8 X\n SG_ S m1x : 0|8@1+ (1,0) [0|1] \"\" X\n", 2, "bad multiplexer indicator 'm1x'"},
        {"BO_ 100 M: 8 X\n SG_ S m4294967296 : 0|8@1+ (1,0) [0|1] \"\" X\n", 2,
         "bad multiplexer indicator 'm4294967296'"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (+ 1,0) [0|1] \"\" X\n", 2, "bad factor"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (1,0) [-|1] \"\" X\n", 2, "bad minimum"},
        {"BO_ 18446744073709551616 M: 8 X\n", 1, "expected a numeric message id"},
        {"BO_ 100 M: 8 X\n SG_ A M : 0|8@1+ (1,0) [0|1] \"\" X\n SG_ B M : 8|8@1+ (1,0) [0|1] \"\" X\n", 3,
         "second multiplexor"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n SG_ S : 8|8@1+ (1,0) [0|1] \"\" X\n", 3,
         "duplicate signal"},
        {"BO_ 100 M: 8 X\nBO_ 100 N: 8 X\n", 2, "duplicate message id 100"},
        {"BO_ 100 M: 65 X\n", 1, "size must be 0..64"},
        {"BO_ abc M: 8 X\n", 1, "expected a numeric message id"},
        {"BO_ 2684354560 M: 8 X\n", 1, "is not a CAN id"},
        {" SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\n", 1, "signal outside a BO_ message"},
        {"VAL_ 100 Nope 1 \"x\" ;\n", 1, "unknown signal"},
        {"BO_ 100 M: 8 X\n SG_ S : 0|8@1+ (1,0) [0|1] \"\" X\nSIG_VALTYPE_ 100 S : 1;\n", 3, "type must be"},
        {"\x01\x02garbage\xff\n", 1, "unexpected text"},
    };
    for (const auto& c : cases) {
        auto strict = DbcDatabase::parse(c.text, "bad.dbc", DbcDatabase::Mode::Strict);
        ASSERT_FALSE(strict.ok()) << c.text;
        const std::string prefix = "bad.dbc:" + std::to_string(c.line) + ": ";
        EXPECT_EQ(strict.error().message.rfind(prefix, 0), 0U) << strict.error().message;
        EXPECT_NE(strict.error().message.find(c.expected), std::string::npos) << strict.error().message;

        auto lenient = DbcDatabase::parse(c.text, "bad.dbc");
        ASSERT_TRUE(lenient.ok());
        EXPECT_EQ(lenient.value().diagnosticCount(), 1U) << c.text;
        ASSERT_FALSE(lenient.value().diagnostics().empty());
        EXPECT_EQ(lenient.value().diagnostics()[0].line, c.line);
    }
}

TEST(DbcDatabase, LenientModeKeepsTheGoodSignals) {
    const char* text =
        "BO_ 100 M: 8 X\n"
        " SG_ Good1 : 0|8@1+ (1,0) [0|255] \"\" X\n"
        " SG_ Broken : 8|8@1+ (1,0 [0|255] \"\" X\n"
        " SG_ Good2 : 16|8@1+ (1,0) [0|255] \"\" X\n";
    auto r = DbcDatabase::parse(text, "x.dbc");
    ASSERT_TRUE(r.ok());
    const auto* m = r.value().findMessage(100U);
    ASSERT_NE(m, nullptr);
    ASSERT_EQ(m->signals.size(), 2U);
    EXPECT_EQ(m->signals[1].name, "Good2");
    EXPECT_EQ(r.value().diagnostics()[0].message, "x.dbc:3: SG_ Broken: bad offset in (factor,offset)");
}

TEST(DbcDatabase, StrayQuoteEarlyInALargeFileIsOneLongString) {
    // A '"' early in a 4 MB file: every line after it belongs to one quoted string, which is
    // scanned once (scanning the whole statement again for each line it grew by took hours).
    std::string body;
    for (int i = 0; i < 100000; ++i) {
        body += " SG_ S" + std::to_string(i) + " : 0|8@1+ (1,0) [0|1] \"\" X\n";
    }
    const std::string open = "BO_ 100 M: 8 X\nCM_ \"stray\n" + body;
    auto strict = DbcDatabase::parse(open, "big.dbc", DbcDatabase::Mode::Strict);
    ASSERT_FALSE(strict.ok());
    EXPECT_EQ(strict.error().message, "big.dbc:2: unterminated quoted string");
    auto lenient = DbcDatabase::parse(open, "big.dbc");
    ASSERT_TRUE(lenient.ok());
    EXPECT_EQ(lenient.value().diagnosticCount(), 1U);
    EXPECT_TRUE(lenient.value().findMessage(100U)->signals.empty());

    // Closed at the end (an escaped quote on the way): the statements after it parse again.
    const std::string closed = open + "still \\\" inside\";\nBO_ 200 N: 8 X\n SG_ T : 0|8@1+ (1,0) [0|1] \"\" X\n";
    auto r = DbcDatabase::parse(closed, "big.dbc", DbcDatabase::Mode::Strict);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_TRUE(r.value().findMessage(100U)->signals.empty());
    ASSERT_NE(r.value().findMessage(200U), nullptr);
    EXPECT_EQ(r.value().findMessage(200U)->signals.size(), 1U);
}

TEST(DbcDatabase, MissingFileIsAnError) {
    auto r = DbcDatabase::load("/nonexistent/file.dbc");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "open(/nonexistent/file.dbc): No such file or directory (DBC file)");
    EXPECT_THROW(DbcDatabase::loadOrThrow("/nonexistent/file.dbc"), navmap::ipc::DbcError);
}

// docs/architecture.md "Untrusted files": a DBC is a regular file of at most 32 MiB, opened without
// blocking. /dev/zero used to be read until the daemon held 2 GB, and a FIFO blocked start-up.
TEST(DbcDatabase, AFileThatIsNoRegularFileOrTooLargeIsRefusedUnread) {
    const auto dir = std::filesystem::temp_directory_path() / ("navmap-dbc-files-" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    std::filesystem::create_directories(dir);
    const auto fifo = dir / "fifo.dbc";
    ASSERT_EQ(::mkfifo(fifo.c_str(), 0600), 0);
    auto r = DbcDatabase::load(fifo);
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, fifo.string() + ": is a FIFO, not a regular file (DBC file)");
    r = DbcDatabase::load("/dev/zero");
    ASSERT_FALSE(r.ok());
    EXPECT_EQ(r.error().message, "/dev/zero: is a character device, not a regular file (DBC file)");
    // Sparse: 2 GiB that cost no disk, refused on their size before a byte is read.
    const auto big = dir / "big.dbc";
    std::ofstream(big).close();
    for (const std::uint64_t size : {(std::uint64_t{32} << 20) + 1, std::uint64_t{2} << 30}) {
        ASSERT_EQ(::truncate(big.c_str(), static_cast<off_t>(size)), 0);
        r = DbcDatabase::load(big);
        ASSERT_FALSE(r.ok());
        EXPECT_EQ(r.error().message,
                  big.string() + ": " + std::to_string(size) + " bytes, over the limit of 32 MiB (DBC file)");
    }
    // At the limit: read and parsed (32 MiB of blank lines is an empty database).
    ASSERT_EQ(::truncate(big.c_str(), 0), 0);
    {
        std::ofstream out(big, std::ios::binary);
        const std::string lines(1 << 20, '\n');
        for (int i = 0; i < 32; ++i) out << lines;
    }
    r = DbcDatabase::load(big);
    ASSERT_TRUE(r.ok()) << r.error().message;
    std::filesystem::remove_all(dir);
}

TEST(DbcDatabase, ProjectNavmapDbcParsesStrictly) {
    auto r = DbcDatabase::load(navmap::test::dataDir() / "navmap.dbc", DbcDatabase::Mode::Strict);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const auto& db = r.value();
    ASSERT_EQ(db.messages().size(), 3U);
    const auto* pos = db.findMessage(0x6A0U);
    ASSERT_NE(pos, nullptr);
    EXPECT_EQ(pos->name, "NAV_Position");
    const auto* lat = pos->findSignal("NAV_Latitude");
    ASSERT_NE(lat, nullptr);
    EXPECT_TRUE(lat->is_signed);
    EXPECT_EQ(lat->length, 32);
    EXPECT_DOUBLE_EQ(lat->factor, 1e-7);
    const auto* motion = db.findMessage(std::string_view("NAV_Motion"));
    ASSERT_NE(motion, nullptr);
    EXPECT_EQ(motion->findSignal("NAV_FixType")->value_names.at(5), "THREE_D");
    EXPECT_EQ(db.findMessage(std::string_view("NAV_Info"))->multiplexor, 0);
}

class RealDbc : public ::testing::Test {
protected:
    std::filesystem::path m_dir = navmap::test::ipcDataDir() / "dbc";
};

TEST_F(RealDbc, FordLincolnBaseParsesWithoutDiagnostics) {
    auto r = DbcDatabase::load(m_dir / "ford_lincoln_base_pt.dbc", DbcDatabase::Mode::Strict);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const auto& db = r.value();
    EXPECT_EQ(db.messages().size(), 331U);
    const auto* brake = db.findMessage(0x415U);
    ASSERT_NE(brake, nullptr);
    EXPECT_EQ(brake->name, "BrakeSysFeatures");
    const auto* speed = brake->findSignal("Veh_V_ActlBrk");
    ASSERT_NE(speed, nullptr);
    EXPECT_EQ(speed->start_bit, 7);
    EXPECT_EQ(speed->length, 16);
    EXPECT_EQ(speed->byte_order, ByteOrder::Motorola);
    EXPECT_DOUBLE_EQ(speed->factor, 0.01);
    EXPECT_EQ(speed->unit, "kph");
    const auto* yaw = db.findMessage(0x091U)->findSignal("VehYaw_W_Actl");
    ASSERT_NE(yaw, nullptr);
    EXPECT_DOUBLE_EQ(yaw->offset, -6.5);
    EXPECT_DOUBLE_EQ(yaw->minimum, -6.5);
    EXPECT_DOUBLE_EQ(yaw->maximum, 6.6066);
    std::size_t signals = 0;
    for (const auto& m : db.messages()) {
        signals += m.signals.size();
        for (const auto& s : m.signals) {
            EXPECT_EQ(s.byte_order, ByteOrder::Motorola) << s.name;
        }
    }
    EXPECT_GT(signals, 2000U);
}

TEST_F(RealDbc, FordFusion2018Parses) {
    auto r = DbcDatabase::load(m_dir / "ford_fusion_2018_pt.dbc", DbcDatabase::Mode::Strict);
    ASSERT_TRUE(r.ok()) << r.error().message;
    EXPECT_EQ(r.value().messages().size(), 14U);
    const auto* steer = r.value().findMessage(0x076U)->findSignal("SteWhlRelInit_An_Sns");
    ASSERT_NE(steer, nullptr);
    EXPECT_EQ(steer->start_bit, 6);
    EXPECT_EQ(steer->length, 15);
    EXPECT_FALSE(steer->hasRange());  // [0|0]
}

TEST_F(RealDbc, VwMqbIntelSignals) {
    auto r = DbcDatabase::load(m_dir / "vw_mqb.dbc", DbcDatabase::Mode::Strict);
    ASSERT_TRUE(r.ok()) << r.error().message;
    const auto& db = r.value();
    EXPECT_GE(db.messages().size(), 100U);
    const auto* esp21 = db.findMessage(std::string_view("ESP_21"));
    ASSERT_NE(esp21, nullptr);
    EXPECT_EQ(esp21->id, 253U);
    const auto* v = esp21->findSignal("ESP_v_Signal");
    ASSERT_NE(v, nullptr);
    EXPECT_EQ(v->byte_order, ByteOrder::Intel);
    // 123.45 km/h = raw 12345 = 0x3039, little endian in bytes 4..5.
    auto f = esp21->encode({{"ESP_v_Signal", 123.45}});
    ASSERT_TRUE(f.ok()) << f.error().message;
    EXPECT_EQ(f.value().data[4], 0x39);
    EXPECT_EQ(f.value().data[5], 0x30);
    EXPECT_NEAR(*v->decode(std::span(f.value().data.data(), 8)), 123.45, 1e-9);
    const auto* esp02 = db.findMessage(std::string_view("ESP_02"));
    ASSERT_NE(esp02, nullptr);
    const auto* yaw = esp02->findSignal("ESP_Gierrate");
    ASSERT_NE(yaw, nullptr);
    EXPECT_EQ(yaw->start_bit, 40);
    EXPECT_EQ(yaw->length, 14);
    EXPECT_EQ(yaw->unit, "Unit_DegreOfArcPerSecon");
    // The German multi-line CM_ strings were skipped, not parsed as statements.
    EXPECT_EQ(db.diagnosticCount(), 0U);
}
