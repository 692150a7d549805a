// SPDX-License-Identifier: Apache-2.0
// navmapd's TOML configuration: defaults, every section, and clear errors for wrong input.
#include <gtest/gtest.h>

#include <fstream>
#include <iterator>

#include "config.h"

namespace {

using namespace navmap::daemon;

std::optional<DaemonConfig> parse(const std::string& text, std::string* message = nullptr) {
    ConfigError err;
    auto c = parseConfig(text, "navmapd.toml", &err);
    if (message) *message = err.message;
    return c;
}

TEST(DaemonConfig, EmptyFileGivesTheDocumentedDefaults) {
    const auto c = parse("");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->input, InputSource::Sim);
    EXPECT_EQ(c->cache_mb, 128u);
    ASSERT_EQ(c->profiles.size(), 3u);
    EXPECT_EQ(c->profiles[0].name, "cluster");
    EXPECT_EQ(c->profiles[0].width, 1280);
    EXPECT_EQ(c->profiles[0].height, 480);
    EXPECT_EQ(c->profiles[2].view, navmap::render::ViewMode::Bird);
    EXPECT_FALSE(c->orthoimage_ground);  // the land cover
    EXPECT_EQ(c->http_port, 0);          // HTTP is off unless configured
    EXPECT_TRUE(c->http_token.empty());
    EXPECT_TRUE(c->stream_group.empty());
    EXPECT_TRUE(c->stream_uids.empty());
    EXPECT_EQ(c->max_clients_per_transport, 32);
    EXPECT_EQ(c->max_clients_per_uid, 8);
    EXPECT_EQ(c->ring_memory_mb, 64u);
    EXPECT_EQ(c->handshake_timeout_s, 5.0);
    EXPECT_EQ(c->stale_pose_ms, 1000);
    EXPECT_EQ(c->log_level, 6);
}

TEST(DaemonConfig, EverySectionIsRead) {
    const auto c = parse(R"(
[store]
path = "/var/lib/navmap/andorra.navmap"
cache_mb = 64
mount = ["/var/lib/navmap/north.navmap", "south.navmap"]
[input]
source = "replay"
replay_log = "drive.candump"
replay_speed = 2.0
dbc = ["navmap.dbc", "ford_lincoln_base_pt.dbc"]
[[can.signal]]
vss = "Vehicle.Speed"
message = "BrakeSysFeatures"
signal = "Veh_V_ActlBrk"
[render]
style = "night"
ground = "orthoimage"
msaa = 0
[[profile]]
name = "cluster"
width = 1280
height = 480
view = "snail"
[[profile]]
name = "hud"
width = 800
height = 240
fps = 20
orientation = "north-up"
roads = "shadow-volume"
glow_roads = true
label_aura = true
road_selection = false
[control]
socket = "/tmp/c.sock"
mode = 0o600
allowed_uids = [1000, 0]
allowed_gids = [1001]
group = "navmap"
[stream]
http_port = 8080
http_token = "0123456789abcdef-_.~"
tcp_port = 7000
group = "107"
allowed_uids = [1000]
allowed_gids = [1002, 1003]
max_clients_per_transport = 16
max_clients_per_uid = 2
ring_memory_mb = 32
handshake_timeout_s = 1.5
stale_pose_ms = 250
[log]
level = "debug"
)");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->store_path, "/var/lib/navmap/andorra.navmap");
    EXPECT_EQ(c->cache_mb, 64u);
    EXPECT_EQ(c->input, InputSource::Replay);
    EXPECT_EQ(c->replay_speed, 2.0);
    ASSERT_EQ(c->mount_paths.size(), 2u);
    EXPECT_EQ(c->mount_paths[0], "/var/lib/navmap/north.navmap");
    EXPECT_EQ(c->mount_paths[1], "south.navmap");
    ASSERT_EQ(c->dbc_files.size(), 2u);
    EXPECT_NE(c->signal_map_toml.find("Veh_V_ActlBrk"), std::string::npos);
    EXPECT_TRUE(c->night);
    EXPECT_TRUE(c->orthoimage_ground);
    EXPECT_EQ(c->msaa, 0);
    ASSERT_EQ(c->profiles.size(), 2u);
    EXPECT_EQ(c->profiles[1].fps, 20.0);
    EXPECT_EQ(c->profiles[1].orientation, navmap::render::Orientation::NorthUp);
    EXPECT_EQ(c->profiles[0].roads, navmap::render::RoadTechnique::Auto);
    EXPECT_TRUE(c->profiles[0].glow_roads);  // the default: glowing roads in every profile
    EXPECT_EQ(c->profiles[1].roads, navmap::render::RoadTechnique::ShadowVolume);
    EXPECT_TRUE(c->profiles[1].glow_roads);
    EXPECT_TRUE(c->profiles[1].label_aura);
    EXPECT_TRUE(c->profiles[0].road_selection);
    EXPECT_FALSE(c->profiles[1].road_selection);
    EXPECT_EQ(c->control_mode, 0600u);
    EXPECT_EQ(c->control_uids, (std::vector<std::uint32_t>{1000, 0}));
    EXPECT_EQ(c->control_gids, (std::vector<std::uint32_t>{1001}));
    EXPECT_EQ(c->control_group, "navmap");
    EXPECT_EQ(c->tcp_port, 7000);
    EXPECT_EQ(c->http_port, 8080);
    EXPECT_EQ(c->http_token, "0123456789abcdef-_.~");
    EXPECT_EQ(c->stream_group, "107");
    EXPECT_EQ(c->stream_uids, (std::vector<std::uint32_t>{1000}));
    EXPECT_EQ(c->stream_gids, (std::vector<std::uint32_t>{1002, 1003}));
    EXPECT_EQ(c->max_clients_per_transport, 16);
    EXPECT_EQ(c->max_clients_per_uid, 2);
    EXPECT_EQ(c->ring_memory_mb, 32u);
    EXPECT_EQ(c->handshake_timeout_s, 1.5);
    EXPECT_EQ(c->stale_pose_ms, 250);
    EXPECT_EQ(c->log_level, 7);
    ConfigError err;
    EXPECT_TRUE(validateConfig(*c, &err)) << err.message;
}

TEST(DaemonConfig, ErrorsNameFileLineAndProblem) {
    std::string m;
    EXPECT_FALSE(parse("[store]\ncache_mb = \"lots\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:12: store.cache_mb must be an integer");
    EXPECT_FALSE(parse("[store]\ncache_mb = 2\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:12: store.cache_mb = 2 out of range [8, 65536]");
    EXPECT_FALSE(parse("[store]\nmount = [\"a.navmap\", 3]\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:22: store.mount entries must be file names");
    // One file name where a list is wanted was ignored without a word.
    EXPECT_FALSE(parse("[input]\ndbc = \"vehicle.dbc\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:7: input.dbc must be an array of file names");
    EXPECT_FALSE(parse("[store]\nmount = \"north.navmap\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:9: store.mount must be an array of file names");
    EXPECT_FALSE(parse("[render]\nmsaa = 4\nsytle = \"night\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml:3:9: unknown key render.sytle");
    EXPECT_FALSE(parse("[render]\nground = \"satellite\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml: render.ground = \"satellite\": expected landcover or orthoimage");
    EXPECT_FALSE(parse("[render]\nground = true\n", &m));
    EXPECT_EQ(m.rfind("navmapd.toml:2:10: render.ground must be", 0), 0u) << m;
    EXPECT_FALSE(parse("[rendr]\n", &m));
    EXPECT_NE(m.find("unknown section or key 'rendr'"), std::string::npos) << m;
    EXPECT_FALSE(parse("[input]\nsource = \"usb\"\n", &m));
    EXPECT_NE(m.find("expected sim, replay or socketcan"), std::string::npos) << m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"x\"\nview = \"sky\"\n", &m));
    EXPECT_NE(m.find("expected bird, snail or hud"), std::string::npos) << m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"x\"\nroads = \"painted\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml:1:1: profile.roads = \"painted\": expected geometric, shadow-volume or auto") << m;
    EXPECT_FALSE(parse("[stream]\nallowed_uids = [1000, -1]\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:23: stream.allowed_uids entries must be uids");
    EXPECT_FALSE(parse("[control]\nallowed_gids = 5\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:16: control.allowed_gids must be an array of ids");
    EXPECT_FALSE(parse("[stream]\nmax_clients_per_uid = 0\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:23: stream.max_clients_per_uid = 0 out of range [1, 1024]");
    EXPECT_FALSE(parse("[stream]\nstale_pose_ms = 0\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:17: stream.stale_pose_ms = 0 out of range [1, 600000]");
    EXPECT_FALSE(parse("[stream]\nhttp_token = \"short\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml: stream.http_token must be 16..256 characters of A-Z a-z 0-9 - _ . ~");
    EXPECT_FALSE(parse("[stream]\nhttp_token = \"0123456789abcdef&x\"\n", &m));
    EXPECT_NE(m.find("stream.http_token must be"), std::string::npos) << m;
    EXPECT_FALSE(parse("[store\npath = 1", &m));
    EXPECT_EQ(m.rfind("navmapd.toml:1:", 0), 0u) << m;
}

TEST(DaemonConfig, ProfileCameraInMapLibreConvention) {
    auto c = parse(
        "[[profile]]\nname = \"cluster\"\nzoom = 16.5\npitch = 60\norientation = \"north-up\"\n"
        "[[profile]]\nname = \"hud\"\n");
    ASSERT_TRUE(c);
    ASSERT_TRUE(c->profiles[0].camera);
    EXPECT_DOUBLE_EQ(c->profiles[0].camera->zoom, 16.5);
    EXPECT_DOUBLE_EQ(c->profiles[0].camera->pitch_deg, 60.0);
    EXPECT_FALSE(c->profiles[0].camera->bearing_deg) << "the bearing follows the orientation";
    EXPECT_EQ(c->profiles[0].orientation, navmap::render::Orientation::NorthUp);
    EXPECT_FALSE(c->profiles[1].camera) << "no zoom: the view's own rig";
    EXPECT_NE(describeConfig(*c).find("profile cluster: 1280x480 @ 30 fps, snail, north-up, roads auto, glowing roads, "
                                      "label aura, MapLibre camera zoom 16.5 pitch 60\n"),
              std::string::npos)
        << describeConfig(*c);
    // The limits of MapLibre GL JS: zoom 0..24, pitch 0..85.
    c = parse("[[profile]]\nname = \"c\"\nzoom = 0\npitch = 85\n");
    ASSERT_TRUE(c);
    EXPECT_DOUBLE_EQ(c->profiles[0].camera->zoom, 0.0);
    EXPECT_DOUBLE_EQ(c->profiles[0].camera->pitch_deg, 85.0);
}

TEST(DaemonConfig, ProfileCameraErrors) {
    std::string m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"c\"\nzoom = 24.5\npitch = 60\n", &m));
    EXPECT_EQ(m, "navmapd.toml:3:8: profile.zoom = 24.5 out of range [0, 24]");
    EXPECT_FALSE(parse("[[profile]]\nname = \"c\"\nzoom = 16\npitch = 86\n", &m));
    EXPECT_EQ(m, "navmapd.toml:4:9: profile.pitch = 86 out of range [0, 85]");
    EXPECT_FALSE(parse("[[profile]]\nname = \"c\"\nzoom = 16\npitch = -5\n", &m));
    EXPECT_EQ(m, "navmapd.toml:4:9: profile.pitch = -5 out of range [0, 85]");
    EXPECT_FALSE(parse("[[profile]]\nname = \"c\"\nzoom = \"close\"\npitch = 60\n", &m));
    EXPECT_EQ(m, "navmapd.toml:3:8: profile.zoom must be a number");
    EXPECT_FALSE(parse("[[profile]]\nname = \"c\"\nzoom = 16\n", &m));
    EXPECT_EQ(m, "navmapd.toml:1:1: profile.zoom needs profile.pitch (a MapLibre-convention camera gives both)");
    EXPECT_FALSE(parse("[[profile]]\nname = \"c\"\npitch = 60\n", &m));
    EXPECT_EQ(m, "navmapd.toml:1:1: profile.pitch needs profile.zoom (a MapLibre-convention camera gives both)");
}

TEST(DaemonConfig, ValidationCatchesCrossFieldMistakes) {
    auto c = parse("[store]\npath = \"x.navmap\"\n[input]\nsource = \"replay\"\n");
    ASSERT_TRUE(c);
    ConfigError err;
    EXPECT_FALSE(validateConfig(*c, &err));
    EXPECT_EQ(err.message, "input.source = \"replay\" needs input.replay_log");
    c = parse("[store]\npath = \"x\"\n[[profile]]\nname = \"a\"\n[[profile]]\nname = \"a\"\n");
    ASSERT_TRUE(c);
    EXPECT_FALSE(validateConfig(*c, &err));
    EXPECT_EQ(err.message, "profile 'a' defined twice");
}

TEST(DaemonConfig, ControlIdleTimeout) {
    EXPECT_EQ(parse("")->control_idle_timeout_s, 30.0);
    EXPECT_EQ(parse("[control]\nidle_timeout_s = 2.5\n")->control_idle_timeout_s, 2.5);
    EXPECT_EQ(parse("[control]\nidle_timeout_s = 0\n")->control_idle_timeout_s, 0.0);  // never
    std::string m;
    EXPECT_FALSE(parse("[control]\nidle_timeout_s = -1.0\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:18: control.idle_timeout_s = -1 out of range [0, 86400]");
    EXPECT_FALSE(parse("[control]\nidle_timeout_s = nan\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:18: control.idle_timeout_s = nan out of range [0, 86400]");
}

TEST(DaemonConfig, ControlAndStreamSlotsPerPeer) {
    const auto d = parse("");
    ASSERT_TRUE(d);
    EXPECT_EQ(d->control_max_clients_per_uid, 8);
    EXPECT_EQ(d->control_max_subscribers_per_uid, 4);
    EXPECT_TRUE(d->control_privileged_uids.empty());
    EXPECT_EQ(d->max_clients_per_address, 8);
    const auto c = parse(
        "[control]\nmax_clients_per_uid = 3\nmax_subscribers_per_uid = 2\nprivileged_uids = [1000, 1001]\n"
        "[stream]\nmax_clients_per_address = 4\n");
    ASSERT_TRUE(c);
    EXPECT_EQ(c->control_max_clients_per_uid, 3);
    EXPECT_EQ(c->control_max_subscribers_per_uid, 2);
    EXPECT_EQ(c->control_privileged_uids, (std::vector<std::uint32_t>{1000, 1001}));
    EXPECT_EQ(c->max_clients_per_address, 4);
    std::string m;
    EXPECT_FALSE(parse("[control]\nmax_clients_per_uid = 17\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:23: control.max_clients_per_uid = 17 out of range [1, 16]");
    EXPECT_FALSE(parse("[control]\nmax_subscribers_per_uid = 0\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:27: control.max_subscribers_per_uid = 0 out of range [1, 16]");
    EXPECT_FALSE(parse("[control]\nprivileged_uids = [\"hmi\"]\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:20: control.privileged_uids entries must be uids");
    EXPECT_FALSE(parse("[stream]\nmax_clients_per_address = 0\n", &m));
    EXPECT_EQ(m, "navmapd.toml:2:27: stream.max_clients_per_address = 0 out of range [1, 1024]");
}

TEST(DaemonConfig, SpeedLimitSignCornerPerProfile) {
    using navmap::render::SignCorner;
    // The built-in profiles: the cluster and the HUD show it top right, the center display not.
    const auto d = parse("");
    ASSERT_TRUE(d);
    EXPECT_EQ(d->profiles[0].speed_limit_sign, SignCorner::TopRight);
    EXPECT_EQ(d->profiles[1].speed_limit_sign, SignCorner::TopRight);
    EXPECT_FALSE(d->profiles[2].speed_limit_sign);
    const auto c = parse(
        "[[profile]]\nname = \"a\"\nview = \"bird\"\n[[profile]]\nname = \"b\"\nview = \"snail\"\n"
        "[[profile]]\nname = \"c\"\nspeed_limit_sign = \"bottom-left\"\n"
        "[[profile]]\nname = \"d\"\nview = \"hud\"\nspeed_limit_sign = \"off\"\n"
        "[[profile]]\nname = \"e\"\nview = \"bird\"\nspeed_limit_sign = \"top-left\"\n");
    ASSERT_TRUE(c);
    EXPECT_FALSE(c->profiles[0].speed_limit_sign);
    EXPECT_EQ(c->profiles[1].speed_limit_sign, SignCorner::TopRight);
    EXPECT_EQ(c->profiles[2].speed_limit_sign, SignCorner::BottomLeft);
    EXPECT_FALSE(c->profiles[3].speed_limit_sign);
    EXPECT_EQ(c->profiles[4].speed_limit_sign, SignCorner::TopLeft);
    std::string m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"x\"\nspeed_limit_sign = \"middle\"\n", &m));
    EXPECT_EQ(m,
              "navmapd.toml:1:1: profile.speed_limit_sign = \"middle\": expected top-left, top-right, bottom-left, "
              "bottom-right or off");
    // The shipped configuration file says the same as the built-in defaults.
    std::ifstream shipped(std::string(NAVMAP_SOURCE_DIR) + "/daemon/navmapd.toml");
    const std::string text((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
    const auto f = parse(text, &m);
    ASSERT_TRUE(f) << m;
    for (std::size_t i = 0; i < 3; ++i)
        EXPECT_EQ(f->profiles[i].speed_limit_sign, d->profiles[i].speed_limit_sign) << i;
}

TEST(DaemonConfig, StreetBarPerProfile) {
    // The built-in profiles: the cluster shows it, the HUD and the center display not.
    const auto d = parse("");
    ASSERT_TRUE(d);
    EXPECT_TRUE(d->profiles[0].street_bar);
    EXPECT_FALSE(d->profiles[1].street_bar);
    EXPECT_FALSE(d->profiles[2].street_bar);
    // Without the key the view decides: on in snail's views only.
    const auto c = parse(
        "[[profile]]\nname = \"a\"\nview = \"bird\"\n[[profile]]\nname = \"b\"\nview = \"snail\"\n"
        "[[profile]]\nname = \"c\"\nview = \"hud\"\n"
        "[[profile]]\nname = \"d\"\nstreet_bar = false\n"
        "[[profile]]\nname = \"e\"\nview = \"bird\"\nstreet_bar = true\n");
    ASSERT_TRUE(c);
    EXPECT_FALSE(c->profiles[0].street_bar);
    EXPECT_TRUE(c->profiles[1].street_bar);
    EXPECT_FALSE(c->profiles[2].street_bar);
    EXPECT_FALSE(c->profiles[3].street_bar);
    EXPECT_TRUE(c->profiles[4].street_bar);
    std::string m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"x\"\nstreet_bar = \"yes\"\n", &m));
    EXPECT_EQ(m, "navmapd.toml:3:14: profile.street_bar must be true or false");
}

TEST(DaemonConfig, LaneGuidancePerProfileAndItsDistance) {
    // The built-in profiles: the cluster and the HUD show the lanes, the center display not.
    const auto d = parse("");
    ASSERT_TRUE(d);
    EXPECT_TRUE(d->profiles[0].lane_guidance);
    EXPECT_TRUE(d->profiles[1].lane_guidance);
    EXPECT_FALSE(d->profiles[2].lane_guidance);
    EXPECT_DOUBLE_EQ(d->guidance.lane_distance_m, 500.0);
    const auto c = parse(
        "[guidance]\nlane_distance_m = 300.0\n"
        "[[profile]]\nname = \"a\"\nview = \"bird\"\n[[profile]]\nname = \"b\"\nview = \"hud\"\n"
        "[[profile]]\nname = \"c\"\nlane_guidance = false\n"
        "[[profile]]\nname = \"d\"\nview = \"bird\"\nlane_guidance = true\n");
    ASSERT_TRUE(c);
    EXPECT_DOUBLE_EQ(c->guidance.lane_distance_m, 300.0);
    EXPECT_FALSE(c->profiles[0].lane_guidance);
    EXPECT_TRUE(c->profiles[1].lane_guidance);
    EXPECT_FALSE(c->profiles[2].lane_guidance);
    EXPECT_TRUE(c->profiles[3].lane_guidance);
    std::string m;
    EXPECT_FALSE(parse("[guidance]\nlane_distance_m = -5.0\n", &m));
    EXPECT_NE(m.find("guidance.lane_distance_m = -5 out of range [0, 5000]"), std::string::npos) << m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"x\"\nlane_guidance = \"yes\"\n", &m));
    EXPECT_NE(m.find("lane_guidance"), std::string::npos) << m;
    // The shipped configuration file says the same as the built-in defaults.
    std::ifstream shipped(std::string(NAVMAP_SOURCE_DIR) + "/daemon/navmapd.toml");
    const std::string text((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
    const auto f = parse(text, &m);
    ASSERT_TRUE(f) << m;
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(f->profiles[i].street_bar, d->profiles[i].street_bar) << i;
    EXPECT_DOUBLE_EQ(f->guidance.lane_distance_m, 500.0);
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(f->profiles[i].lane_guidance, d->profiles[i].lane_guidance) << i;
}

TEST(DaemonConfig, AttributionFollowsTheViewUnlessSet) {
    // The built-in profiles: the center display (bird's-eye) carries it, cluster and HUD do not.
    const auto d = parse("");
    ASSERT_TRUE(d);
    EXPECT_FALSE(d->profiles[0].attribution);
    EXPECT_FALSE(d->profiles[1].attribution);
    EXPECT_TRUE(d->profiles[2].attribution);
    const auto c = parse(
        "[[profile]]\nname = \"a\"\nview = \"bird\"\n[[profile]]\nname = \"b\"\nview = \"snail\"\n"
        "[[profile]]\nname = \"c\"\nview = \"bird\"\nattribution = false\n"
        "[[profile]]\nname = \"d\"\nview = \"hud\"\nattribution = true\n");
    ASSERT_TRUE(c);
    EXPECT_TRUE(c->profiles[0].attribution);
    EXPECT_FALSE(c->profiles[1].attribution);
    EXPECT_FALSE(c->profiles[2].attribution);
    EXPECT_TRUE(c->profiles[3].attribution);
    EXPECT_NE(
        describeConfig(*c).find(
            "profile d: 1280x480 @ 30 fps, snail, heading-up, roads auto, glowing roads, label aura, attribution\n"),
        std::string::npos)
        << describeConfig(*c);
    std::string m;
    EXPECT_FALSE(parse("[[profile]]\nname = \"x\"\nattribution = \"yes\"\n", &m));
    EXPECT_NE(m.find("profile.attribution"), std::string::npos) << m;
    // The shipped configuration file says the same as the built-in defaults.
    std::ifstream shipped(std::string(NAVMAP_SOURCE_DIR) + "/daemon/navmapd.toml");
    const std::string text((std::istreambuf_iterator<char>(shipped)), std::istreambuf_iterator<char>());
    const auto f = parse(text, &m);
    ASSERT_TRUE(f) << m;
    for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(f->profiles[i].attribution, d->profiles[i].attribution) << i;
}

}  // namespace
