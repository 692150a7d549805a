// SPDX-License-Identifier: Apache-2.0
#pragma once
// navmapd's configuration: one TOML file (toml++), every key optional with a documented default
// (docs/navmapd.md, daemon/navmapd.toml), command-line overrides applied on top.

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "profiles.h"

namespace navmap::daemon {

enum class InputSource { Sim, Replay, SocketCan };

/// Route guidance (docs/guidance.md): off-route hysteresis and the manoeuvre arrows.
struct GuidanceConfig {
    double off_route_distance_m = 40.0;  ///< farther from the route than this ...
    double off_route_time_s = 3.0;       ///< ... for this long: off_route
    double on_route_distance_m = 20.0;   ///< within this of the route ...
    double on_route_time_s = 2.0;        ///< ... for this long: back_on_route
    /// The manoeuvre after the next gets a fainter arrow when it follows within this distance.
    double second_arrow_within_m = 250.0;
    /// Lane guidance: the lanes of the last way with turn lanes at most this far before the next
    /// junction, shown from this distance on (docs/guidance.md "Lanes").
    double lane_distance_m = 500.0;
};

/// [style]: how the map chooses between its day and night style (docs/navmapd.md "Day and night").
struct StyleConfig {
    /// mode = "auto": the sun or the vehicle's lights choose (DayNight); "day" / "night": fixed,
    /// DaemonConfig::night. set_style overrides either until set_style "auto".
    bool automatic = false;
    /// source = "can": a light signal the DBC maps (docs/can-input.md) while one is heard, else the
    /// sun; "sun": the sun only.
    bool prefer_can = true;
    double twilight_deg = -6.0;           ///< night while the sun is below this (civil twilight) ...
    double hysteresis_deg = 1.0;          ///< ... crossed by half of this either way before the style changes
    double light_night_below_pct = 10.0;  ///< Vehicle.Exterior.LightIntensity: night below this ...
    double light_day_above_pct = 20.0;    ///< ... day above this, the last style between
    double can_timeout_s = 10.0;          ///< a light signal older than this counts as none (the sun decides)
    double fade_s = 2.0;                  ///< the cross-fade between the styles
};

struct DaemonConfig {
    // [store]
    std::filesystem::path store_path;  ///< compiled tile store: the map's frame and road graph
    /// More stores drawn with it (region packages; map::StoreSet, docs/tile-store.md "Several stores").
    std::vector<std::filesystem::path> mount_paths;
    std::size_t cache_mb = 128;  ///< tile cache budget
    // [input]
    InputSource input = InputSource::Sim;
    std::filesystem::path replay_log;  ///< candump log (input = "replay")
    double replay_speed = 1.0;
    bool replay_loop = true;
    std::string can_interface = "can0";            ///< input = "socketcan"
    std::vector<std::filesystem::path> dbc_files;  ///< empty: the shipped navmap.dbc
    double stale_after_s = 2.0;                    ///< position shown as lost after this
    std::string signal_map_toml;                   ///< [[can.signal]] tables (raw TOML), empty: navmap.dbc defaults
    // [sim]
    std::string sim_from = "andorra-la-vella";
    std::string sim_to = "encamp";
    double sim_speed_factor = 1.0;
    GuidanceConfig guidance;
    // [render]
    std::string egl_platform = "auto";
    int msaa = -1;
    bool night = false;  ///< the style while StyleConfig::automatic is off ([style] mode, or render.style)
    StyleConfig style;
    /// The terrain's ground: false the OpenStreetMap land cover, true the synthetic orthoimage
    /// (seed ch. 6; tiles with ortho layers, weights <datadir>/ortho-mlp.nnw; docs/orthoimage.md).
    bool orthoimage_ground = false;
    bool labels = true;  ///< place, POI, road and area names
    /// GPU tiles kept (one renderer serves all profiles; a tile any profile drew in its latest
    /// frame is always kept, the cap bounds the others); 0 = automatic (16 + 8 per profile, at least 32).
    int gpu_tile_cache = 0;
    /// Shader caches (docs/navmapd.md "Start-up"): linked programs as driver binaries in
    /// <dir>/programs, and Mesa's own cache in <dir>/mesa unless MESA_SHADER_CACHE_DIR is set.
    /// Empty: $CACHE_DIRECTORY (systemd's CacheDirectory=) when set, else none.
    std::filesystem::path shader_cache;
    std::vector<DisplayProfile> profiles;  ///< [[profile]]; defaults: cluster, hud, center
    // [control]
    std::filesystem::path control_socket = "/run/navmap/control.sock";
    std::uint32_t control_mode = 0660;
    std::vector<std::uint32_t> control_uids;  ///< empty: same uid as the daemon, and root
    std::vector<std::uint32_t> control_gids;  ///< allowed_gids: members (primary or supplementary) may connect
    std::string control_group;                ///< socket file group (name or gid), its members allowed; empty: none
    double control_idle_timeout_s = 30.0;     ///< connections without traffic are closed after this; 0: never
    int control_max_clients_per_uid = 8;      ///< connections per unprivileged peer uid
    int control_max_subscribers_per_uid = 4;  ///< subscribed connections per unprivileged peer uid
    /// privileged_uids: with root and the daemon's own uid, they take an unprivileged slot when all are taken
    std::vector<std::uint32_t> control_privileged_uids;
    // [stream]
    std::filesystem::path frame_socket = "/run/navmap/frames.sock";
    std::string stream_group;                ///< socket file group (name or gid), its members allowed; empty: none
    std::vector<std::uint32_t> stream_uids;  ///< allowed_uids; empty: same uid as the daemon, and root
    std::vector<std::uint32_t> stream_gids;  ///< allowed_gids
    int max_clients_per_transport = 32;      ///< Unix, TCP and HTTP connections, each
    int max_clients_per_uid = 8;             ///< Unix connections per peer uid
    int max_clients_per_address = 8;         ///< TCP connections, and HTTP connections, per peer address
    std::size_t ring_memory_mb = 64;         ///< all shared-memory rings together
    double handshake_timeout_s = 5.0;        ///< handshake, then first frame, each within this
    int tcp_port = 0;                        ///< 0: no TCP frame server
    int http_port = 0;                       ///< MJPEG, status page, /metrics; 0: off
    std::string http_address = "127.0.0.1";
    std::string http_token;         ///< empty: no token; else Bearer token or ?token=
    double client_timeout_s = 5.0;  ///< stalled clients are disconnected after this
    /// A frame is stale_pose when its pose's newest fix is older than this (docs/frame-protocol.md).
    int stale_pose_ms = 1000;
    // [log]
    int log_level = 6;                  ///< syslog priority: 3 err .. 7 debug
    double watchdog_max_frame_s = 2.0;  ///< WATCHDOG=1 only while a frame finished this recently
};

/// At most this many [[profile]] tables: each is a renderer's display with its own frames.
inline constexpr std::size_t kMaxProfiles = 64;

/// What went wrong in a config file: "<file>:<line>:<column>: <problem>".
struct ConfigError {
    std::string message;
};

/// Parses TOML text; unknown keys are errors (typos must not pass silently). Text nested deeper or
/// holding more values than TomlLimits' defaults is refused before toml++ parses it (toml_limits.h).
std::optional<DaemonConfig> parseConfig(const std::string& text, const std::string& source_name, ConfigError* error);
/// Reads the file (a regular file of at most 4 MiB, opened without blocking: a FIFO or a device
/// is an error naming what it is; docs/architecture.md "Untrusted files") and parses it.
std::optional<DaemonConfig> loadConfig(const std::filesystem::path& path, ConfigError* error);

/// Checks cross-field rules (profiles unique and sane, a replay log for input = replay, ...).
bool validateConfig(const DaemonConfig& config, ConfigError* error);

/// A human-readable dump of the effective configuration (navmapd --check-config).
std::string describeConfig(const DaemonConfig& config);

}  // namespace navmap::daemon
