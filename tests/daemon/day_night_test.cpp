// SPDX-License-Identifier: Apache-2.0
// Day and night (docs/navmapd.md "Day and night"): the sun's elevation against published values,
// the style the daemon chooses by the sun at simulated places and times, the style a CAN light
// signal chooses (a candump replayed through the daemon's own input: DBC, signal map, decoder),
// hysteresis at both thresholds, and set_style winning over both until set_style auto.

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <functional>
#include <string>
#include <thread>
#include <vector>

#include "config.h"
#include "day_night.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/map/projection.h"
#include "navmap/map/road_graph.h"
#include "sun_position.h"
#include "test_paths.h"
#include "vehicle_input.h"

using namespace navmap;
using namespace navmap::daemon;
using namespace std::chrono_literals;

namespace {

std::chrono::system_clock::time_point utc(int y, unsigned mo, unsigned d, int h, int mi, double s = 0.0) {
    const std::chrono::sys_days day = std::chrono::year(y) / std::chrono::month(mo) / std::chrono::day(d);
    return day + std::chrono::hours(h) + std::chrono::minutes(mi) +
           std::chrono::duration_cast<std::chrono::system_clock::duration>(std::chrono::duration<double>(s));
}

struct Published {
    const char* what;
    double lat_deg, lon_deg;
    std::chrono::system_clock::time_point t;
    double elevation_deg;
};

}  // namespace

// Published elevations, each within 0.2 degrees (measured: under 0.02).
// - Golden, Colorado, 2003-10-17 12:30:30 MST (19:30:30 UT): the worked example of I. Reda and
//   A. Andreas, "Solar Position Algorithm for Solar Radiation Applications", NREL/TP-560-34302
//   (2003, rev. 2008), Table A5.1: topocentric zenith angle 50.11162 degrees (refraction at
//   820 mbar and 11 C included, about 0.016 degrees of it), elevation 39.88838.
// - The December solstice 2024, 21 Dec 09:20 UT, and the March equinox 2024, 20 Mar 03:06 UT
//   (U.S. Naval Observatory, Astronomical Applications Department, "Earth's Seasons and
//   Apsides"): the apparent declination is then -23.436 degrees (the true obliquity of 2024,
//   The Astronomical Almanac 2024, B61) and 0. At the longitude where it is local apparent noon
//   at that instant (the equation of time +1.6 min and -7.4 min, Astronomical Almanac C5-C19),
//   the sun culminates at 90 - |latitude - declination|: Moscow's latitude 55.75 N at 39.6 E
//   gives 10.814, Adelaide's 34.93 S at 135.4 E gives 55.07. A minute off noon changes these by
//   under 0.001 degrees.
TEST(SunPosition, ElevationMatchesPublishedValuesWithinAFifthOfADegree) {
    const Published cases[] = {
        {"NREL SPA example, Golden CO", 39.742476, -105.1786, utc(2003, 10, 17, 19, 30, 30.0), 90.0 - 50.11162},
        {"December solstice 2024, 55.75 N 39.6 E", 55.75, 39.6, utc(2024, 12, 21, 9, 20), 90.0 - 55.75 - 23.436},
        {"March equinox 2024, 34.93 S 135.4 E", -34.93, 135.4, utc(2024, 3, 20, 3, 6), 90.0 - 34.93},
    };
    for (const auto& c : cases) {
        const double got = solarElevationDeg(c.lat_deg, c.lon_deg, c.t);
        std::printf("%s: %.4f, published %.4f, error %+.4f deg\n", c.what, got, c.elevation_deg, got - c.elevation_deg);
        EXPECT_NEAR(got, c.elevation_deg, 0.2) << c.what;
    }
}

TEST(SunPosition, NightSideAndMidnightSun) {
    // Midnight at Andorra in December: far below the horizon (about -68 degrees).
    EXPECT_LT(solarElevationDeg(42.5, 1.5, utc(2024, 12, 21, 23, 0)), -60.0);
    // Tromsø at midnight in late June: the sun stays above the horizon (about +2.5 degrees).
    const double midnight_sun = solarElevationDeg(69.65, 18.96, utc(2024, 6, 21, 22, 50));
    EXPECT_GT(midnight_sun, 0.0);
    EXPECT_LT(midnight_sun, 6.0);
}

namespace {

DayNightInput autoAt(double lat, double lon, std::chrono::system_clock::time_point t, double now_s) {
    DayNightInput in;
    in.requested = ipc::MapStyle::Auto;
    in.lat_deg = lat;
    in.lon_deg = lon;
    in.wall_time = t;
    in.can_now = ipc::CanTime(std::chrono::seconds(1'700'000'000));
    in.now_s = now_s;
    return in;
}

}  // namespace

TEST(DayNight, ChoosesBySunAtTheSimulatedPlaceAndTime) {
    StyleConfig config;
    config.automatic = true;
    // Andorra la Vella (42.51 N, 1.52 E) on 2024-12-21: sunset about 16:40 UT, civil dusk about
    // 17:12 UT. At noon day, at 19:00 UT night.
    DayNight noon(config);
    const auto day_style = noon.update(autoAt(42.51, 1.52, utc(2024, 12, 21, 12, 0), 0.0));
    EXPECT_FALSE(noon.night());
    EXPECT_EQ(noon.reason(), StyleReason::Sun);
    EXPECT_EQ(day_style.sky_color, render::MapStyle::day().sky_color);
    ASSERT_TRUE(noon.sunElevationDeg());
    EXPECT_NEAR(*noon.sunElevationDeg(), 90.0 - 42.51 - 23.44, 0.6);  // near the culmination

    DayNight evening(config);
    const auto night_style = evening.update(autoAt(42.51, 1.52, utc(2024, 12, 21, 19, 0), 0.0));
    EXPECT_TRUE(evening.night());
    EXPECT_EQ(night_style.sky_color, render::MapStyle::night().sky_color) << "the first frame shows it at once";
    // The same instant is broad day in Sydney (33.87 S, 151.21 E; 06:00 local summer time).
    DayNight sydney(config);
    (void)sydney.update(autoAt(-33.87, 151.21, utc(2024, 12, 21, 19, 0), 0.0));
    EXPECT_FALSE(sydney.night());
}

TEST(DayNight, DuskFadesOverTwoSecondsWithHysteresisAtTheThreshold) {
    StyleConfig config;
    config.automatic = true;
    DayNight dn(config);
    // Andorra, 2024-12-21: step the clock through civil dusk a minute per frame.
    const auto t0 = utc(2024, 12, 21, 16, 50);
    (void)dn.update(autoAt(42.51, 1.52, t0, 0.0));
    ASSERT_FALSE(dn.night());
    double switched_at_deg = 0.0;
    double frame_s = 0.0;
    for (int minute = 1; minute < 60 && !dn.night(); ++minute) {
        frame_s = minute;
        (void)dn.update(autoAt(42.51, 1.52, t0 + std::chrono::minutes(minute), frame_s));
        if (dn.night()) switched_at_deg = *dn.sunElevationDeg();
    }
    ASSERT_TRUE(dn.night());
    // Night from half the hysteresis band below -6 degrees, not at -6.
    EXPECT_LT(switched_at_deg, -6.5);
    EXPECT_GT(switched_at_deg, -6.5 - 0.3);  // the sun sinks about 0.17 degrees a minute here
    EXPECT_FLOAT_EQ(dn.weight(), 0.0f) << "the fade starts at the frame that decides";
    // The fade by frame time: halfway after one second, night after two.
    const auto dusk = t0 + std::chrono::minutes(int(frame_s));
    (void)dn.update(autoAt(42.51, 1.52, dusk, frame_s + 1.0));
    EXPECT_NEAR(dn.weight(), 0.5f, 1e-6);
    const auto night_style = dn.update(autoAt(42.51, 1.52, dusk, frame_s + 2.0));
    EXPECT_EQ(dn.weight(), 1.0f);
    EXPECT_EQ(night_style.sky_color, render::MapStyle::night().sky_color);
    // Back above -6 but within the band: still night (no flicker at the threshold).
    StyleConfig wide = config;
    wide.hysteresis_deg = 1.0;
    DayNight held(wide);
    (void)held.update(autoAt(42.51, 1.52, utc(2024, 12, 21, 19, 0), 0.0));  // night
    // Dawn on 2024-12-22: civil dawn (-6) about 07:09 UT; at -5.7 the style holds, at -5.4 day.
    bool day_seen_above_deg = false;
    for (int minute = 0; minute < 90; ++minute) {
        const auto t = utc(2024, 12, 22, 6, 30) + std::chrono::minutes(minute);
        const double e = solarElevationDeg(42.51, 1.52, t);
        (void)held.update(autoAt(42.51, 1.52, t, 100.0 + minute));
        if (e > -6.0 && e < -5.5) {
            EXPECT_TRUE(held.night()) << "at " << e << " deg";
        }
        if (!held.night()) {
            EXPECT_GT(e, -5.5);
            day_seen_above_deg = true;
            break;
        }
    }
    EXPECT_TRUE(day_seen_above_deg);
}

TEST(DayNight, SetStyleWinsUntilAuto) {
    StyleConfig config;
    config.automatic = true;
    ipc::ControlState control;
    ipc::SetStyleCommand command;
    command.style = ipc::MapStyle::Auto;
    ASSERT_TRUE(control.setStyle(command));
    DayNight dn(config);
    auto in = autoAt(42.51, 1.52, utc(2024, 12, 21, 12, 0), 0.0);  // noon: the sun says day
    in.requested = control.view()->style;
    (void)dn.update(in);
    EXPECT_FALSE(dn.night());
    command.style = ipc::MapStyle::Night;  // the HMI
    ASSERT_TRUE(control.setStyle(command));
    in.requested = control.view()->style;
    in.now_s = 1.0;
    (void)dn.update(in);
    EXPECT_TRUE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Fixed);
    EXPECT_FALSE(dn.sunElevationDeg());
    command.style = ipc::MapStyle::Auto;
    ASSERT_TRUE(control.setStyle(command));
    in.requested = control.view()->style;
    in.now_s = 2.0;
    (void)dn.update(in);
    EXPECT_FALSE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Sun);
}

namespace {

std::filesystem::path fixture(const char* name) { return test::sourceDir() / "tests/daemon/data" / name; }

// The daemon's input (VehicleInput: its DBC files and [[can.signal]] map, the replay source, the
// decoder) replaying tests/daemon/data/lights.candump with `signals` mapped; each light snapshot
// it publishes goes through DayNight in auto mode at Andorra's noon (the sun says day). Returns
// the style decided after each change of the light, in order, and the reasons.
struct Decision {
    bool night;
    StyleReason reason;
};
std::vector<Decision> replayLights(const std::string& signals, DayNight& dn, ipc::ControlState& control,
                                   const std::function<void(int)>& between = {}) {
    const std::string toml = "[input]\nsource = \"replay\"\nreplay_log = \"" + fixture("lights.candump").string() +
                             "\"\nreplay_speed = 2.0\nreplay_loop = false\ndbc = [\"" + fixture("lights.dbc").string() +
                             "\"]\n" + signals;
    ConfigError error;
    const auto config = parseConfig(toml, "lights.toml", &error);
    EXPECT_TRUE(config) << error.message;
    if (!config) return {};
    auto shared = std::shared_ptr<ipc::ControlState>(&control, [](ipc::ControlState*) {});
    VehicleInput input(*config, map::Projection(42.51, 1.52), {}, {}, std::make_shared<const map::RoadGraph>(), shared,
                       test::dataDir());
    // The snapshot before the first frame: each frame's new one is a change, however soon it comes.
    std::shared_ptr<const AmbientLight> seen = input.ambientLight();
    input.start();
    std::vector<Decision> out;
    const auto until = std::chrono::steady_clock::now() + 10s;
    int changes = 0;
    double now_s = 0.0;
    while (std::chrono::steady_clock::now() < until && changes < 6) {
        const auto light = input.ambientLight();
        if (light != seen) {
            seen = light;
            ++changes;
            auto in = autoAt(42.51, 1.52, utc(2024, 12, 21, 12, 0), now_s += 3.0);
            in.requested = control.view()->style;
            in.light = *light;
            in.can_now = ipc::CanClock::now();
            (void)dn.update(in);
            out.push_back({dn.night(), dn.reason()});
            if (between) between(changes);
        }
        std::this_thread::sleep_for(2ms);
    }
    input.stop();
    return out;
}

}  // namespace

TEST(DayNight, AmbientLightFromCanChoosesWithHysteresis) {
    StyleConfig config;
    config.automatic = true;
    DayNight dn(config);
    ipc::ControlState control;
    ipc::SetStyleCommand command;
    command.style = ipc::MapStyle::Auto;
    ASSERT_TRUE(control.setStyle(command));
    const auto d = replayLights(
        "[[can.signal]]\nvss = \"Vehicle.Exterior.LightIntensity\"\nmessage = \"BCM_Lights\"\n"
        "signal = \"BCM_AmbientLight\"\n[[can.signal]]\nvss = \"Vehicle.Body.Lights.Beam.Low.IsOn\"\n"
        "message = \"BCM_Lights\"\nsignal = \"BCM_LowBeam\"\n",
        dn, control);
    // 80 %, 50 %, 15 % (in the band: day stays), 5 % night, 15 % (night stays), 25 % day though
    // the low beam is still on: the intensity says how dark it is.
    ASSERT_EQ(d.size(), 6u);
    const bool expected[] = {false, false, false, true, true, false};
    for (std::size_t i = 0; i < d.size(); ++i) {
        EXPECT_EQ(d[i].night, expected[i]) << "frame " << i;
        EXPECT_EQ(d[i].reason, StyleReason::Can) << "frame " << i;
    }
}

TEST(DayNight, LowBeamFromCanChoosesAndSetStyleOverridesIt) {
    StyleConfig config;
    config.automatic = true;
    DayNight dn(config);
    ipc::ControlState control;
    ipc::SetStyleCommand command;
    command.style = ipc::MapStyle::Auto;
    ASSERT_TRUE(control.setStyle(command));
    // After the fourth frame (low beam on) the HMI asks for day; after the fifth, auto again.
    const auto d = replayLights(
        "[[can.signal]]\nvss = \"Vehicle.Body.Lights.Beam.Low.IsOn\"\nmessage = \"BCM_Lights\"\n"
        "signal = \"BCM_LowBeam\"\n",
        dn, control, [&](int change) {
            ipc::SetStyleCommand c;
            if (change == 4) c.style = ipc::MapStyle::Day;
            if (change == 5) c.style = ipc::MapStyle::Auto;
            if (c.style) {
                EXPECT_TRUE(control.setStyle(c));
            }
        });
    // The low beam's frames only: off, off, off, on, on, on.
    ASSERT_EQ(d.size(), 6u);
    EXPECT_FALSE(d[0].night);
    EXPECT_FALSE(d[2].night);
    EXPECT_TRUE(d[3].night);
    EXPECT_EQ(d[3].reason, StyleReason::Can);
    EXPECT_FALSE(d[4].night) << "set_style day wins over the lights";
    EXPECT_EQ(d[4].reason, StyleReason::Fixed);
    EXPECT_TRUE(d[5].night) << "set_style auto gives the choice back";
    EXPECT_EQ(d[5].reason, StyleReason::Can);
}

TEST(DayNight, WithoutAFreshLightSignalTheSunDecides) {
    StyleConfig config;
    config.automatic = true;
    DayNight dn(config);
    auto in = autoAt(42.51, 1.52, utc(2024, 12, 21, 12, 0), 0.0);
    in.light.low_beam = true;
    in.light.low_beam_time = in.can_now - 11s;  // older than can_timeout_s
    (void)dn.update(in);
    EXPECT_FALSE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Sun);
    in.light.low_beam_time = in.can_now - 1s;
    in.now_s = 1.0;
    (void)dn.update(in);
    EXPECT_TRUE(dn.night());
    // source = "sun": the lights are not asked.
    config.prefer_can = false;
    DayNight sun_only(config);
    (void)sun_only.update(in);
    EXPECT_FALSE(sun_only.night());
}

TEST(DayNight, ConfigStyleSection) {
    ConfigError error;
    auto c = parseConfig("[style]\nmode = \"auto\"\nsource = \"sun\"\ntwilight_deg = -4.0\n", "t.toml", &error);
    ASSERT_TRUE(c) << error.message;
    EXPECT_TRUE(c->style.automatic);
    EXPECT_FALSE(c->style.prefer_can);
    EXPECT_EQ(c->style.twilight_deg, -4.0);
    EXPECT_EQ(configuredStyle(*c), ipc::MapStyle::Auto);
    c = parseConfig("", "t.toml", &error);
    ASSERT_TRUE(c);
    EXPECT_EQ(configuredStyle(*c), ipc::MapStyle::Day) << "the shipped default stays day";
    EXPECT_FALSE(parseConfig("[style]\nmode = \"dusk\"\n", "t.toml", &error));
    EXPECT_EQ(error.message, "t.toml: style.mode = \"dusk\": expected day, night or auto");
    EXPECT_FALSE(parseConfig("[render]\nstyle = \"night\"\n[style]\nmode = \"auto\"\n", "t.toml", &error));
    EXPECT_EQ(error.message, "t.toml: style.mode and render.style both given: keep style.mode");
    EXPECT_FALSE(parseConfig("[style]\nsource = \"moon\"\n", "t.toml", &error));
    EXPECT_FALSE(parseConfig("[style]\nlight_night_below_pct = 30.0\nlight_day_above_pct = 20.0\n", "t.toml", &error));
}

// In a tunnel the style fades to night over fade_s (reason "tunnel") in the configuration's day
// mode and in auto by day, and back to day after it; a day style the HMI fixed with set_style
// wins, and set_style auto gives the tunnel back.
TEST(DayNight, ATunnelDimsToNightUnlessTheHmiFixedDay) {
    StyleConfig config;
    config.fade_s = 2.0;
    ipc::ControlState control;
    ipc::SetStyleCommand command;
    command.style = ipc::MapStyle::Day;
    command.configured = true;  // the configuration's mode, as navmapd applies it
    ASSERT_TRUE(control.setStyle(command));
    EXPECT_FALSE(control.view()->style_from_hmi);
    DayNight dn(config);
    auto in = autoAt(42.51, 1.52, utc(2024, 12, 21, 12, 0), 0.0);  // noon
    in.requested = control.view()->style;
    in.requested_by_hmi = control.view()->style_from_hmi;
    (void)dn.update(in);
    EXPECT_FALSE(dn.night());
    in.in_tunnel = true;
    in.now_s = 10.0;
    (void)dn.update(in);
    EXPECT_TRUE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Tunnel);
    EXPECT_STREQ(styleReasonName(dn.reason()), "tunnel");
    EXPECT_FLOAT_EQ(dn.weight(), 0.0f) << "the fade starts";
    in.now_s = 11.0;
    const render::MapStyle half = dn.update(in);
    EXPECT_NEAR(dn.weight(), 0.5f, 0.01f);
    EXPECT_LT(half.brightness, render::MapStyle::day().brightness);
    in.now_s = 12.0;
    const render::MapStyle dimmed = dn.update(in);
    EXPECT_FLOAT_EQ(dn.weight(), 1.0f);
    EXPECT_FLOAT_EQ(dimmed.brightness, render::MapStyle::night().brightness);
    in.in_tunnel = false;  // out: back to the mode's day
    in.now_s = 20.0;
    (void)dn.update(in);
    EXPECT_FALSE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Fixed);
    in.now_s = 22.0;
    (void)dn.update(in);
    EXPECT_FLOAT_EQ(dn.weight(), 0.0f);
    // Auto by day: the tunnel wins too.
    in.requested = ipc::MapStyle::Auto;
    in.in_tunnel = true;
    in.now_s = 30.0;
    (void)dn.update(in);
    EXPECT_TRUE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Tunnel);
    // The HMI fixes day: day in the tunnel.
    command.style = ipc::MapStyle::Day;
    command.configured = false;
    ASSERT_TRUE(control.setStyle(command));
    EXPECT_TRUE(control.view()->style_from_hmi);
    in.requested = control.view()->style;
    in.requested_by_hmi = control.view()->style_from_hmi;
    in.now_s = 40.0;
    (void)dn.update(in);
    EXPECT_FALSE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Fixed);
    // The HMI gives the choice back: night in the tunnel again.
    command.style = ipc::MapStyle::Auto;
    ASSERT_TRUE(control.setStyle(command));
    in.requested = control.view()->style;
    in.requested_by_hmi = control.view()->style_from_hmi;
    in.now_s = 50.0;
    (void)dn.update(in);
    EXPECT_TRUE(dn.night());
    EXPECT_EQ(dn.reason(), StyleReason::Tunnel);
}
