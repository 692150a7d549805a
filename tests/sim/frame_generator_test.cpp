// SPDX-License-Identifier: Apache-2.0
// FrameGenerator: rates, decoding back through ipc::VehicleDecoder, noise, dropouts, bad frames,
// determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <map>

#include "navmap/sim/candump_writer.h"
#include "navmap/sim/frame_generator.h"
#include "sim_test_util.h"

namespace navmap::sim {
namespace {

struct Generated {
    std::vector<ipc::CanFrame> frames;
    std::vector<FrameKind> kinds;
    FrameStats stats;
    std::vector<Interval> dropouts;
};

std::shared_ptr<const SpeedProfile> cornerProfile() {
    return std::make_shared<const SpeedProfile>(
        SpeedProfile::build(driveRouteFromPolyline(test::corner(600.0), 60.0f)));
}

FrameGenerator makeGenerator(const std::shared_ptr<const SpeedProfile>& profile, const FrameOptions& o) {
    auto g = FrameGenerator::create(test::navmapDbc(), profile, test::andorraProjection(), o,
                                    [](map::PlanarPoint p) { return 1000.0 + p.x * 0.01; });
    EXPECT_TRUE(g.ok()) << (g.ok() ? "" : g.error().message);
    return std::move(g).value();
}

Generated generate(const std::shared_ptr<const SpeedProfile>& profile, const FrameOptions& o) {
    FrameGenerator g = makeGenerator(profile, o);
    Generated out;
    ipc::CanFrame f;
    FrameKind k{};
    while (g.next(f, &k)) {
        out.frames.push_back(f);
        out.kinds.push_back(k);
    }
    out.stats = g.stats();
    out.dropouts = g.dropouts();
    return out;
}

double secondsOf(const ipc::CanFrame& f, const FrameOptions& o) {
    return std::chrono::duration<double>(f.timestamp - o.start_time).count();
}

TEST(FrameGenerator, RatesAndOrder) {
    const auto profile = cornerProfile();
    FrameOptions o;
    const Generated g = generate(profile, o);
    const double total = profile->duration() + 2 * o.standstill_s;
    EXPECT_NEAR(g.stats.duration_s, total, 0.02);
    const auto& k = g.stats.by_kind;
    EXPECT_NEAR(static_cast<double>(k[static_cast<int>(FrameKind::Position)]), total * 10, 1.5);
    EXPECT_NEAR(static_cast<double>(k[static_cast<int>(FrameKind::Motion)]), total * 50, 1.5);
    EXPECT_NEAR(static_cast<double>(k[static_cast<int>(FrameKind::Info)]), total * 1, 1.5);
    EXPECT_EQ(k[static_cast<int>(FrameKind::BadDlc)] + k[static_cast<int>(FrameKind::BadGarbage)] +
                  k[static_cast<int>(FrameKind::BadOutOfRange)],
              0U);
    for (std::size_t i = 1; i < g.frames.size(); ++i) {
        ASSERT_LE(g.frames[i - 1].timestamp, g.frames[i].timestamp) << i;
    }
    // Ids and lengths are exactly the DBC's.
    std::map<std::uint32_t, std::size_t> ids;
    for (const auto& f : g.frames) {
        ++ids[f.id];
        EXPECT_EQ(f.len, 8);
        EXPECT_EQ(f.flags, 0);
    }
    EXPECT_EQ(ids.size(), 3U);
    EXPECT_EQ(g.frames.front().timestamp, o.start_time);

    FrameOptions five = o;
    five.position_hz = 5.0;
    const Generated g5 = generate(profile, five);
    EXPECT_NEAR(static_cast<double>(g5.stats.by_kind[static_cast<int>(FrameKind::Position)]), total * 5, 1.5);
}

TEST(FrameGenerator, DecodesBackToTheDrive) {
    const auto profile = cornerProfile();
    FrameOptions o;
    FrameGenerator gen = makeGenerator(profile, o);
    ipc::VehicleDecoder dec = test::navmapDecoder();
    const map::Projection proj = test::andorraProjection();
    ipc::CanFrame f;
    std::size_t positions = 0, motions = 0, altitudes = 0;
    double max_pos_err = 0.0, max_speed_err = 0.0, max_heading_err = 0.0, max_yaw_err = 0.0;
    while (gen.next(f)) {
        ipc::VehicleSample s;
        dec.decode(f, s);  // NAV_Info page 1 (UTC time) has no mapped quantity
        const double t = secondsOf(f, o);
        const VehicleState truth = gen.truthAt(t);
        if (s.get(ipc::VssSignal::Latitude)) {
            ++positions;
            const auto p = proj.forward(*s.get(ipc::VssSignal::Latitude), *s.get(ipc::VssSignal::Longitude));
            max_pos_err = std::max(max_pos_err, std::hypot(p.x - truth.position.x, p.y - truth.position.y));
        }
        if (s.get(ipc::VssSignal::Speed)) {
            ++motions;
            max_speed_err = std::max(max_speed_err, std::abs(*s.get(ipc::VssSignal::Speed) - truth.speed_mps * 3.6));
            double dh = std::abs(*s.get(ipc::VssSignal::Heading) - truth.heading_deg);
            dh = std::min(dh, 360.0 - dh);
            max_heading_err = std::max(max_heading_err, dh);
            max_yaw_err = std::max(max_yaw_err, std::abs(*s.get(ipc::VssSignal::YawRate) - truth.yaw_rate_dps));
            EXPECT_EQ(*s.get(ipc::VssSignal::FixType), 5.0);
        }
        if (s.get(ipc::VssSignal::Altitude)) {
            ++altitudes;
            EXPECT_NEAR(*s.get(ipc::VssSignal::Altitude), 1000.0 + truth.position.x * 0.01, 0.006);
        }
    }
    EXPECT_GT(positions, 100U);
    EXPECT_GT(motions, 500U);
    EXPECT_GT(altitudes, 3U);
    EXPECT_LT(max_pos_err, 0.02);  // 1e-7 degree quantization is about 1 cm
    EXPECT_LE(max_speed_err, 0.0051);
    EXPECT_LE(max_heading_err, 0.0051);
    EXPECT_LE(max_yaw_err, 0.0051);
    EXPECT_EQ(dec.counters().rejected, 0U);
    EXPECT_EQ(dec.counters().counter_gaps, 0U);
    EXPECT_EQ(dec.counters().short_frames, 0U);
}

TEST(FrameGenerator, NoiseHasTheConfiguredSigma) {
    const auto profile = cornerProfile();
    FrameOptions o;
    o.noise_m = 3.0;
    FrameGenerator gen = makeGenerator(profile, o);
    ipc::VehicleDecoder dec = test::navmapDecoder();
    const map::Projection proj = test::andorraProjection();
    ipc::CanFrame f;
    double sum2 = 0.0, sum_x = 0.0;
    std::size_t n = 0;
    while (gen.next(f)) {
        ipc::VehicleSample s;
        dec.decode(f, s);
        if (!s.get(ipc::VssSignal::Latitude)) continue;
        const VehicleState truth = gen.truthAt(secondsOf(f, o));
        const auto p = proj.forward(*s.get(ipc::VssSignal::Latitude), *s.get(ipc::VssSignal::Longitude));
        const double dx = p.x - truth.position.x, dy = p.y - truth.position.y;
        sum2 += dx * dx + dy * dy;
        sum_x += dx;
        ++n;
        EXPECT_LT(std::hypot(dx, dy), 6 * o.noise_m);  // within noise
    }
    ASSERT_GT(n, 300U);
    const double sigma = std::sqrt(sum2 / (2.0 * static_cast<double>(n)));
    EXPECT_NEAR(sigma, o.noise_m, 0.15 * o.noise_m);
    EXPECT_NEAR(sum_x / static_cast<double>(n), 0.0, 0.5);
}

TEST(FrameGenerator, SameSeedSameBytesOtherSeedOtherBytes) {
    const auto profile = cornerProfile();
    FrameOptions o;
    o.noise_m = 2.0;
    o.dropouts = 2;
    o.bad_bursts = 3;
    auto text = [&](const FrameOptions& opt) {
        std::string all;
        for (const auto& f : generate(profile, opt).frames) all += formatCandumpLine(f, "can0") + "\n";
        return all;
    };
    const std::string a = text(o);
    EXPECT_EQ(a, text(o));
    FrameOptions other = o;
    other.seed = 2;
    EXPECT_NE(a, text(other));
}

TEST(FrameGenerator, DropoutsRemovePositionFramesAndReportNoFix) {
    const auto profile = cornerProfile();
    FrameOptions o;
    o.dropouts = 3;
    o.dropout_s = 4.0;
    const Generated g = generate(profile, o);
    ASSERT_EQ(g.dropouts.size(), 3U);
    for (std::size_t i = 0; i < g.dropouts.size(); ++i) {
        EXPECT_NEAR(g.dropouts[i].end_s - g.dropouts[i].begin_s, 4.0, 1e-9);
        if (i > 0) {
            EXPECT_GT(g.dropouts[i].begin_s, g.dropouts[i - 1].end_s);
        }
    }
    auto in_dropout = [&](double t) {
        for (const auto& d : g.dropouts) {
            if (t >= d.begin_s && t < d.end_s) return true;
        }
        return false;
    };
    ipc::VehicleDecoder dec = test::navmapDecoder();
    std::size_t nofix = 0;
    for (std::size_t i = 0; i < g.frames.size(); ++i) {
        const double t = secondsOf(g.frames[i], o);
        ipc::VehicleSample s;
        dec.decode(g.frames[i], s);
        if (g.kinds[i] == FrameKind::Position) {
            EXPECT_FALSE(in_dropout(t)) << t;
        }
        if (g.kinds[i] == FrameKind::Motion) {
            EXPECT_EQ(*s.get(ipc::VssSignal::FixType), in_dropout(t) ? 0.0 : 5.0) << t;
            nofix += in_dropout(t) ? 1 : 0;
        }
    }
    EXPECT_NEAR(static_cast<double>(nofix), 3 * 4.0 * 50, 3.0);
    const double total = g.stats.duration_s;
    EXPECT_NEAR(static_cast<double>(g.stats.by_kind[static_cast<int>(FrameKind::Position)]), (total - 12.0) * 10, 4.0);
    // Motion keeps its counter going through a dropout.
    EXPECT_EQ(dec.counters().counter_gaps, 0U);
}

TEST(FrameGenerator, BadFrameBurstsAppearAsConfigured) {
    const auto profile = cornerProfile();
    FrameOptions o;
    o.bad_bursts = 20;
    o.burst_frames = 6;
    const Generated g = generate(profile, o);
    const auto& k = g.stats.by_kind;
    const std::uint64_t dlc = k[static_cast<int>(FrameKind::BadDlc)];
    const std::uint64_t garbage = k[static_cast<int>(FrameKind::BadGarbage)];
    const std::uint64_t range = k[static_cast<int>(FrameKind::BadOutOfRange)];
    EXPECT_EQ(dlc + garbage + range, 120U);
    EXPECT_GT(dlc, 10U);
    EXPECT_GT(garbage, 10U);
    EXPECT_GT(range, 10U);
    ipc::VehicleDecoder dec = test::navmapDecoder();
    std::size_t short_frames = 0;
    for (std::size_t i = 0; i < g.frames.size(); ++i) {
        ipc::VehicleSample s;
        dec.decode(g.frames[i], s);
        if (g.kinds[i] == FrameKind::BadDlc) {
            EXPECT_LT(g.frames[i].len, g.frames[i].id == 0x6A0 ? 8 : 7);
            ++short_frames;
        }
        if (g.kinds[i] == FrameKind::BadOutOfRange) {
            // The bad value is rejected: no latitude / heading comes out of this frame.
            EXPECT_FALSE(s.get(ipc::VssSignal::Latitude).has_value());
            EXPECT_FALSE(s.get(ipc::VssSignal::Heading).has_value());
        }
    }
    EXPECT_EQ(dec.counters().short_frames, short_frames);
    EXPECT_GE(dec.counters().rejected, range + dlc);
    // Bursts: consecutive bad frames 1 ms apart.
    std::size_t runs = 0;
    for (std::size_t i = 0; i < g.kinds.size(); ++i) {
        const bool bad = g.kinds[i] >= FrameKind::BadDlc;
        if (bad && (i == 0 || g.kinds[i - 1] < FrameKind::BadDlc)) ++runs;
    }
    EXPECT_GE(runs, 20U);  // a regular frame may land inside a burst
}

TEST(FrameGenerator, MaxDurationCutsTheDrive) {
    const auto profile = cornerProfile();
    FrameOptions o;
    o.max_duration_s = 10.0;
    const Generated g = generate(profile, o);
    EXPECT_NEAR(g.stats.duration_s, 10.0, 1e-9);
    EXPECT_EQ(g.stats.by_kind[static_cast<int>(FrameKind::Motion)], 501U);  // 0, 20 ms, ..., 10 s
}

TEST(FrameGenerator, RejectsBadOptions) {
    const auto profile = cornerProfile();
    auto fails = [&](FrameOptions o, const std::string& what) {
        auto g = FrameGenerator::create(test::navmapDbc(), profile, test::andorraProjection(), o);
        ASSERT_FALSE(g.ok());
        EXPECT_NE(g.error().message.find(what), std::string::npos) << g.error().message;
    };
    FrameOptions o;
    o.position_hz = 0;
    fails(o, "position rate");
    o = {};
    o.motion_hz = 5000;
    fails(o, "motion rate");
    o = {};
    o.noise_m = -1;
    fails(o, "noise");
    o = {};
    o.burst_frames = 0;
    fails(o, "burst size");
    auto other = ipc::DbcDatabase::parse("BO_ 1696 Other: 8 X\n SG_ A : 0|8@1+ (1,0) [0|0] \"\" X\n", "other.dbc");
    ASSERT_TRUE(other.ok());
    auto g = FrameGenerator::create(std::make_shared<const ipc::DbcDatabase>(std::move(other).value()), profile,
                                    test::andorraProjection(), FrameOptions{});
    ASSERT_FALSE(g.ok());
    EXPECT_EQ(g.error().message, "navmap DBC has no message NAV_Position");
}

}  // namespace
}  // namespace navmap::sim
