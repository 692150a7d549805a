// SPDX-License-Identifier: Apache-2.0
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>

#include "navmap/ipc/can/candump_reader.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/signal_map.h"
#include "navmap/ipc/can/vehicle_decoder.h"
#include "test_paths.h"

using navmap::ipc::CanFrame;
using navmap::ipc::CanTime;
using navmap::ipc::DbcDatabase;
using navmap::ipc::SignalMap;
using navmap::ipc::VehicleDecoder;
using navmap::ipc::VehicleSample;
using navmap::ipc::VssSignal;

namespace {

std::shared_ptr<const DbcDatabase> loadDbc(const std::filesystem::path& p) {
    auto r = DbcDatabase::load(p, DbcDatabase::Mode::Strict);
    EXPECT_TRUE(r.ok()) << (r.ok() ? "" : r.error().message);
    return r.ok() ? std::make_shared<const DbcDatabase>(std::move(r).value()) : nullptr;
}

std::shared_ptr<const DbcDatabase> navmapDbc() { return loadDbc(navmap::test::dataDir() / "navmap.dbc"); }

VehicleDecoder navmapDecoder() {
    auto d = VehicleDecoder::create({navmapDbc()}, SignalMap::navmapDefaults());
    EXPECT_TRUE(d.ok()) << (d.ok() ? "" : d.error().message);
    return std::move(d).value();
}

CanFrame encode(const DbcDatabase& db, const char* message, const std::map<std::string, double, std::less<>>& v,
                int ms = 0) {
    auto f = db.findMessage(std::string_view(message))->encode(v);
    EXPECT_TRUE(f.ok()) << (f.ok() ? "" : f.error().message);
    CanFrame frame = f.ok() ? f.value() : CanFrame{};
    frame.timestamp = CanTime(std::chrono::seconds(100) + std::chrono::milliseconds(ms));
    return frame;
}

}  // namespace

TEST(VehicleDecoder, NavmapDbcRoundTrip) {
    const auto db = navmapDbc();
    VehicleDecoder dec = navmapDecoder();
    VehicleSample u;
    // Ordino, Andorra (El Serrat, on the CG-3).
    ASSERT_TRUE(dec.decode(encode(*db, "NAV_Position", {{"NAV_Latitude", 42.623636}, {"NAV_Longitude", 1.532909}}), u));
    EXPECT_NEAR(*u.get(VssSignal::Latitude), 42.623636, 0.6e-7);
    EXPECT_NEAR(*u.get(VssSignal::Longitude), 1.532909, 0.6e-7);
    EXPECT_FALSE(u.get(VssSignal::Speed).has_value());
    EXPECT_EQ(u.source_time, CanTime(std::chrono::seconds(100)));

    ASSERT_TRUE(dec.decode(encode(*db, "NAV_Motion",
                                  {{"NAV_Heading", 271.25},
                                   {"NAV_Speed", 48.3},
                                   {"NAV_YawRate", -3.5},
                                   {"NAV_FixType", 5},
                                   {"NAV_Counter", 7},
                                   {"NAV_NumSatellites", 11}},
                                  10),
                           u));
    EXPECT_NEAR(*u.get(VssSignal::Heading), 271.25, 1e-9);
    EXPECT_NEAR(*u.get(VssSignal::Speed), 48.3, 1e-9);
    EXPECT_NEAR(*u.get(VssSignal::YawRate), -3.5, 1e-9);
    EXPECT_EQ(*u.get(VssSignal::FixType), 5.0);
    EXPECT_EQ(*u.get(VssSignal::GnssCounter), 7.0);

    // Southern/western hemisphere and the extremes of the range.
    ASSERT_TRUE(dec.decode(encode(*db, "NAV_Position", {{"NAV_Latitude", -90.0}, {"NAV_Longitude", -179.9999999}}), u));
    EXPECT_NEAR(*u.get(VssSignal::Latitude), -90.0, 1e-9);
    EXPECT_NEAR(*u.get(VssSignal::Longitude), -179.9999999, 1e-9);

    // Multiplexed NAV_Info: page 0 altitude, page 1 time (not mapped).
    ASSERT_TRUE(
        dec.decode(encode(*db, "NAV_Info", {{"NAV_InfoPage", 0}, {"NAV_Altitude", 1302.45}, {"NAV_Hdop", 0.9}}), u));
    EXPECT_NEAR(*u.get(VssSignal::Altitude), 1302.45, 1e-9);
    EXPECT_FALSE(dec.decode(encode(*db, "NAV_Info", {{"NAV_InfoPage", 1}, {"NAV_UtcTime", 1.7e9}}), u));

    const VehicleSample& latest = dec.latest();
    EXPECT_NEAR(*latest.get(VssSignal::Latitude), -90.0, 1e-9);
    EXPECT_NEAR(*latest.get(VssSignal::Speed), 48.3, 1e-9);
    EXPECT_EQ(latest.timeOf(VssSignal::Speed), CanTime(std::chrono::seconds(100) + std::chrono::milliseconds(10)));
    EXPECT_EQ(dec.counters().rejected, 0U);
    EXPECT_EQ(dec.frameKeys(), (std::vector<std::uint32_t>{0x6A0, 0x6A1, 0x6A2}));
}

TEST(VehicleDecoder, OutOfRangeValuesAreRejectedAndCounted) {
    const auto db = navmapDbc();
    VehicleDecoder dec = navmapDecoder();
    VehicleSample u;
    // 95 degrees fits the 32 bits but not the DBC range [-90|90]; longitude is fine.
    ASSERT_TRUE(dec.decode(encode(*db, "NAV_Position", {{"NAV_Latitude", 95.0}, {"NAV_Longitude", 10.0}}), u));
    EXPECT_FALSE(u.get(VssSignal::Latitude).has_value());
    EXPECT_NEAR(*u.get(VssSignal::Longitude), 10.0, 1e-7);
    EXPECT_FALSE(dec.decode(encode(*db, "NAV_Position", {{"NAV_Latitude", -200.0}, {"NAV_Longitude", 200.0}}), u));
    EXPECT_EQ(dec.counters().rejected, 3U);
    EXPECT_EQ(dec.mappingStats()[0].rejected, 2U);
    EXPECT_NE(dec.mappingStats()[0].last_rejection.find("outside the DBC range"), std::string::npos)
        << dec.mappingStats()[0].last_rejection;
    // Heading 400 is outside [0|360].
    ASSERT_TRUE(dec.decode(encode(*db, "NAV_Motion", {{"NAV_Heading", 400}, {"NAV_Speed", 10}}), u));
    EXPECT_FALSE(u.get(VssSignal::Heading).has_value());
    EXPECT_FALSE(dec.latest().get(VssSignal::Latitude).has_value());  // never accepted
}

TEST(VehicleDecoder, ShortErrorAndRemoteFrames) {
    const auto db = navmapDbc();
    VehicleDecoder dec = navmapDecoder();
    VehicleSample u;
    CanFrame f = encode(*db, "NAV_Position", {{"NAV_Latitude", 42.5}, {"NAV_Longitude", 1.5}});
    f.len = 4;  // only latitude fits
    ASSERT_TRUE(dec.decode(f, u));
    EXPECT_TRUE(u.get(VssSignal::Latitude).has_value());
    EXPECT_FALSE(u.get(VssSignal::Longitude).has_value());
    EXPECT_EQ(dec.counters().short_frames, 1U);
    EXPECT_NE(dec.mappingStats()[1].last_rejection.find("frame has 4 bytes"), std::string::npos);
    f.flags |= navmap::ipc::kCanRtr;
    EXPECT_FALSE(dec.decode(f, u));
    CanFrame err;
    err.id = 0x6A0;
    err.flags = navmap::ipc::kCanError;
    err.len = 8;
    EXPECT_FALSE(dec.decode(err, u));
    EXPECT_EQ(dec.counters().ignored_frames, 2U);
    CanFrame ext = encode(*db, "NAV_Position", {{"NAV_Latitude", 42.5}});
    ext.flags |= navmap::ipc::kCanExtended;  // 29-bit 0x6A0 is another frame
    EXPECT_FALSE(dec.decode(ext, u));
    EXPECT_EQ(dec.counters().matched_frames, 1U);
}

TEST(VehicleDecoder, CounterGapsAreCounted) {
    const auto db = navmapDbc();
    VehicleDecoder dec = navmapDecoder();
    VehicleSample u;
    for (const int c : {14, 15, 0, 1, 4, 5}) {  // wraps at 16; 2 and 3 are lost
        ASSERT_TRUE(dec.decode(encode(*db, "NAV_Motion", {{"NAV_Counter", c}}), u));
    }
    EXPECT_EQ(dec.counters().counter_gaps, 2U);
}

TEST(SignalMap, TomlParsingAndErrors) {
    auto ok = SignalMap::fromToml(R"(
[[can.signal]]
vss = "Vehicle.Speed"
message = "0x415"
signal = "Veh_V_ActlBrk"
scale = 0.5
bias = 1

[[can.signal]]
vss = "Vehicle.AngularVelocity.Yaw"
message = "ESP_02"
signal = "ESP_Gierrate"
sign_signal = "ESP_VZ_Gierrate"
unit = "deg/s"
)",
                                  "cfg.toml", "can.signal");
    ASSERT_TRUE(ok.ok()) << ok.error().message;
    ASSERT_EQ(ok.value().mappings().size(), 2U);
    EXPECT_EQ(ok.value().mappings()[0].target, VssSignal::Speed);
    EXPECT_DOUBLE_EQ(ok.value().mappings()[0].scale, 0.5);
    EXPECT_EQ(ok.value().mappings()[1].sign_signal, "ESP_VZ_Gierrate");

    const std::pair<const char*, const char*> bad[] = {
        {"[[signal]]\nvss = \"Vehicle.Sped\"\nmessage=\"a\"\nsignal=\"b\"\n",
         "cfg.toml:2: signal #1: unknown VSS name 'Vehicle.Sped'"},
        {"[[signal]]\nvss = \"Vehicle.Speed\"\nmessage=\"a\"\n",
         "cfg.toml:1: signal #1: 'vss', 'message' and 'signal' are required"},
        {"[[signal]]\nvss = \"Vehicle.Speed\"\nmessage=\"a\"\nsignal=\"b\"\nfactor=2\n", "unknown key 'factor'"},
        {"[[signal]]\nvss = \"Vehicle.Speed\"\nmessage=1\nsignal=\"b\"\n", "'message' must be a string"},
        {"[[signal]]\nvss = \"Vehicle.Speed\"\nmessage=\"a\"\nsignal=\"b\"\nscale=\"x\"\n", "'scale' must be a number"},
        {"signal = 3\n", "must be an array of tables"},
        {"other = 3\n", "no [[signal]] entries"},
        {"[[signal]\n", "cfg.toml:1:"},
    };
    for (const auto& [text, expected] : bad) {
        auto r = SignalMap::fromToml(text, "cfg.toml");
        ASSERT_FALSE(r.ok()) << text;
        EXPECT_NE(r.error().message.find(expected), std::string::npos) << r.error().message;
    }
}

TEST(SignalMap, UnitConversions) {
    using navmap::ipc::unitConversion;
    EXPECT_DOUBLE_EQ(*unitConversion("kph", VssSignal::Speed), 1.0);
    EXPECT_DOUBLE_EQ(*unitConversion("m/s", VssSignal::Speed), 3.6);
    EXPECT_DOUBLE_EQ(*unitConversion("Unit_KiloMeterPerHour", VssSignal::Speed), 1.0);
    EXPECT_NEAR(*unitConversion("rad/s", VssSignal::YawRate), 180.0 / std::numbers::pi, 1e-12);
    EXPECT_DOUBLE_EQ(*unitConversion("Unit_DegreOfArcPerSecon", VssSignal::YawRate), 1.0);
    EXPECT_DOUBLE_EQ(*unitConversion("deg", VssSignal::Latitude), 1.0);
    EXPECT_FALSE(unitConversion("rpm", VssSignal::Speed).has_value());
    EXPECT_FALSE(unitConversion("deg/s", VssSignal::Speed).has_value());
    EXPECT_FALSE(unitConversion("", VssSignal::Speed).has_value());
    EXPECT_DOUBLE_EQ(*unitConversion("whatever", VssSignal::FixType), 1.0);
}

TEST(VehicleDecoder, CreateFailsOnBadMappings) {
    const auto db = navmapDbc();
    SignalMap m1;
    m1.add({VssSignal::Speed, "NoSuchMessage", "X", {}, {}, 1.0, 0.0, {}});
    auto r1 = VehicleDecoder::create({db}, m1);
    ASSERT_FALSE(r1.ok());
    EXPECT_EQ(r1.error().message,
              "signal map Vehicle.Speed <- NoSuchMessage.X: message 'NoSuchMessage' is in none of the DBC files");
    SignalMap m2;
    m2.add({VssSignal::Speed, "NAV_Motion", "NAV_Sped", {}, {}, 1.0, 0.0, {}});
    auto r2 = VehicleDecoder::create({db}, m2);
    ASSERT_FALSE(r2.ok());
    EXPECT_NE(r2.error().message.find("has no signal 'NAV_Sped'"), std::string::npos);
    SignalMap m3;
    m3.add({VssSignal::Speed, "NAV_Motion", "NAV_Heading", {}, {}, 1.0, 0.0, {}});  // deg -> km/h
    auto r3 = VehicleDecoder::create({db}, m3);
    ASSERT_FALSE(r3.ok());
    EXPECT_NE(r3.error().message.find("cannot convert unit 'deg' to 'km/h'"), std::string::npos);
    SignalMap m4;
    m4.add({VssSignal::Speed, "0x6A1", "NAV_Speed", "other.dbc", {}, 1.0, 0.0, {}});
    EXPECT_FALSE(VehicleDecoder::create({db}, m4).ok());
    SignalMap m5;
    m5.add({VssSignal::Speed, "1697", "NAV_Speed", "navmap.dbc", {}, 1.0, 0.0, {}});
    EXPECT_TRUE(VehicleDecoder::create({db}, m5).ok());
}

class RealLogs : public ::testing::Test {
protected:
    void SetUp() override {
        m_dir = navmap::test::ipcDataDir();
        static std::shared_ptr<const DbcDatabase> base = loadDbc(m_dir / "dbc" / "ford_lincoln_base_pt.dbc");
        static std::shared_ptr<const DbcDatabase> fusion = loadDbc(m_dir / "dbc" / "ford_fusion_2018_pt.dbc");
        auto map = SignalMap::loadToml(m_dir / "ford_fusion_signals.toml");
        ASSERT_TRUE(map.ok()) << map.error().message;
        m_map = map.value();
        m_dbs = {base, fusion, navmapDbc()};
    }

    struct Series {
        std::vector<double> speed;
        std::vector<double> yaw_rad_s;
        std::vector<double> steer;
        std::uint64_t rejected = 0;
    };

    Series decodeLog(const char* name) {
        Series s;
        auto log = navmap::ipc::loadCandumpFile(m_dir / "can" / name);
        EXPECT_TRUE(log.ok());
        if (!log.ok()) {
            return s;
        }
        auto dec = VehicleDecoder::create(m_dbs, m_map);
        EXPECT_TRUE(dec.ok()) << (dec.ok() ? "" : dec.error().message);
        VehicleSample u;
        for (const auto& rec : log.value().records) {
            if (!dec.value().decode(rec.frame, u)) {
                continue;
            }
            if (const auto v = u.get(VssSignal::Speed)) {
                s.speed.push_back(*v);
            }
            if (const auto v = u.get(VssSignal::YawRate)) {
                s.yaw_rad_s.push_back(*v * std::numbers::pi / 180.0);
            }
            if (const auto v = u.get(VssSignal::SteeringWheelAngle)) {
                s.steer.push_back(*v);
            }
        }
        s.rejected = dec.value().counters().rejected;
        return s;
    }

    std::filesystem::path m_dir;
    SignalMap m_map;
    std::vector<std::shared_ptr<const DbcDatabase>> m_dbs;
};

namespace {

double minOf(const std::vector<double>& v) { return *std::min_element(v.begin(), v.end()); }
double maxOf(const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); }
double meanOfFirst(const std::vector<double>& v, std::size_t n) {
    n = std::min(n, v.size());
    double s = 0;
    for (std::size_t i = 0; i < n; ++i) s += v[i];
    return s / static_cast<double>(n);
}
double meanOfLast(const std::vector<double>& v, std::size_t n) {
    n = std::min(n, v.size());
    double s = 0;
    for (std::size_t i = v.size() - n; i < v.size(); ++i) s += v[i];
    return s / static_cast<double>(n);
}

}  // namespace

// Expected values from tests/ipc/data/SOURCES.md (decoded speed, yaw rate, steering-wheel angle).
struct SteadyLog {
    const char* file;
    double speed_min, speed_max, yaw_min, yaw_max, steer_min, steer_max;
};

TEST_F(RealLogs, SteadySpeedLogsMatchTheirNames) {
    const SteadyLog logs[] = {
        {"ford_fusion_2017_acc_on_going_at_50km_per_hour.candump", 46.9, 47.2, -0.009, 0.005, -1.0, 0.8},
        {"ford_fusion_2017_acc_on_going_at_60km_per_hour.candump", 57.2, 58.5, -0.008, 0.014, -1.4, 2.2},
        {"ford_fusion_2017_lane_keep_assist_on_green_lines.candump", 63.7, 64.2, -0.002, 0.002, -0.1, 0.0},
        {"ford_fusion_2017_lane_keep_assist_on_red_lines.candump", 102.7, 103.7, -0.016, 0.049, -1.3, 7.3},
        {"ford_fusion_2017_lane_keep_assist_on_yellow_right_line.candump", 66.2, 66.8, -0.006, 0.018, -0.9, 2.9},
    };
    for (const auto& e : logs) {
        SCOPED_TRACE(e.file);
        const Series s = decodeLog(e.file);
        ASSERT_GT(s.speed.size(), 50U);
        EXPECT_NEAR(minOf(s.speed), e.speed_min, 0.06);
        EXPECT_NEAR(maxOf(s.speed), e.speed_max, 0.06);
        ASSERT_GT(s.yaw_rad_s.size(), 50U);
        EXPECT_NEAR(minOf(s.yaw_rad_s), e.yaw_min, 0.0006);
        EXPECT_NEAR(maxOf(s.yaw_rad_s), e.yaw_max, 0.0006);
        ASSERT_GT(s.steer.size(), 50U);
        EXPECT_NEAR(minOf(s.steer), e.steer_min, 0.06);
        EXPECT_NEAR(maxOf(s.steer), e.steer_max, 0.06);
        EXPECT_EQ(s.rejected, 0U);
    }
}

TEST_F(RealLogs, AcceleratingAndBrakingLogs) {
    const Series up = decodeLog("ford_fusion_2017_acc_on_speed_changing_from_30km_to_80km_per_hour.candump");
    ASSERT_GT(up.speed.size(), 100U);
    EXPECT_NEAR(minOf(up.speed), 27.8, 0.06);
    EXPECT_NEAR(maxOf(up.speed), 75.8, 0.06);
    EXPECT_LT(meanOfFirst(up.speed, 20), 30.0);
    EXPECT_GT(meanOfLast(up.speed, 20), 74.0);
    EXPECT_NEAR(minOf(up.yaw_rad_s), -0.028, 0.0006);
    EXPECT_NEAR(maxOf(up.yaw_rad_s), 0.019, 0.0006);

    const Series down = decodeLog("ford_fusion_2017_acc_on_speed_changing_from_80km_to_30km_per_hour.candump");
    EXPECT_NEAR(maxOf(down.speed), 75.8, 0.06);
    EXPECT_NEAR(minOf(down.speed), 27.1, 0.06);
    EXPECT_GT(meanOfFirst(down.speed, 20), 74.0);
    EXPECT_LT(meanOfLast(down.speed, 20), 29.0);
}

TEST_F(RealLogs, LkasLongTwoInterfacesComesToAStop) {
    const Series s = decodeLog("ford_fusion_2017_lkas-long.candump");
    ASSERT_GT(s.speed.size(), 100U);
    EXPECT_NEAR(maxOf(s.speed), 12.8, 0.06);
    // Starts near 10 km/h, peaks at 12.8 in the first third, then stops.
    EXPECT_NEAR(meanOfFirst(s.speed, 5), 10.0, 0.5);
    const auto peak = std::max_element(s.speed.begin(), s.speed.end()) - s.speed.begin();
    EXPECT_LT(static_cast<double>(peak), 0.35 * static_cast<double>(s.speed.size()));
    EXPECT_DOUBLE_EQ(meanOfLast(s.speed, 20), 0.0);
    EXPECT_NEAR(minOf(s.yaw_rad_s), -0.035, 0.0006);
    EXPECT_NEAR(maxOf(s.yaw_rad_s), 0.018, 0.0006);
    EXPECT_NEAR(minOf(s.steer), -39.2, 0.06);
    EXPECT_NEAR(maxOf(s.steer), 34.4, 0.06);
}

TEST_F(RealLogs, VehicleDbcCombinesWithGnssNode) {
    auto dec = VehicleDecoder::create(m_dbs, [&] {
        SignalMap m = m_map;
        const SignalMap defaults = SignalMap::navmapDefaults();
        for (const auto& x : defaults.mappings()) {
            m.add(x);
        }
        return m;
    }());
    ASSERT_TRUE(dec.ok()) << dec.error().message;
    auto log = navmap::ipc::loadCandumpFile(m_dir / "can" / "ford_fusion_2017_lane_keep_assist_on_red_lines.candump");
    ASSERT_TRUE(log.ok());
    const auto& nav = *m_dbs[2];
    VehicleSample u;
    for (const auto& rec : log.value().records) {
        dec.value().decode(rec.frame, u);
    }
    EXPECT_TRUE(dec.value().decode(encode(nav, "NAV_Position", {{"NAV_Latitude", 42.5}, {"NAV_Longitude", 1.5}}), u));
    const VehicleSample& latest = dec.value().latest();
    EXPECT_NEAR(*latest.get(VssSignal::Latitude), 42.5, 1e-7);
    EXPECT_NEAR(*latest.get(VssSignal::Speed), 103.2, 0.6);
    EXPECT_TRUE(latest.get(VssSignal::YawRate).has_value());
    EXPECT_FALSE(latest.get(VssSignal::Heading).has_value());
    const auto keys = dec.value().frameKeys();
    EXPECT_TRUE(std::find(keys.begin(), keys.end(), 0x415U) != keys.end());
    EXPECT_TRUE(std::find(keys.begin(), keys.end(), 0x6A0U) != keys.end());
}

TEST(VehicleDecoder, VwSignBitNegatesYawRate) {
    const auto vw = loadDbc(navmap::test::ipcDataDir() / "dbc" / "vw_mqb.dbc");
    SignalMap m;
    m.add({VssSignal::YawRate, "ESP_02", "ESP_Gierrate", {}, {}, 1.0, 0.0, "ESP_VZ_Gierrate"});
    m.add({VssSignal::Speed, "ESP_21", "ESP_v_Signal", {}, {}, 1.0, 0.0, {}});
    auto dec = VehicleDecoder::create({vw}, m);
    ASSERT_TRUE(dec.ok()) << dec.error().message;
    VehicleSample u;
    ASSERT_TRUE(dec.value().decode(encode(*vw, "ESP_02", {{"ESP_Gierrate", 12.5}, {"ESP_VZ_Gierrate", 1}}), u));
    EXPECT_NEAR(*u.get(VssSignal::YawRate), -12.5, 1e-9);
    ASSERT_TRUE(dec.value().decode(encode(*vw, "ESP_02", {{"ESP_Gierrate", 12.5}, {"ESP_VZ_Gierrate", 0}}), u));
    EXPECT_NEAR(*u.get(VssSignal::YawRate), 12.5, 1e-9);
    ASSERT_TRUE(dec.value().decode(encode(*vw, "ESP_21", {{"ESP_v_Signal", 88.88}}), u));
    EXPECT_NEAR(*u.get(VssSignal::Speed), 88.88, 1e-9);
}
