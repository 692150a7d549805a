// SPDX-License-Identifier: Apache-2.0
#include "config.h"

#include <toml++/toml.h>

#include <algorithm>
#include <fstream>
#include <set>
#include <sstream>
#include <utility>

#include "navmap/common/untrusted_file.h"
#include "navmap/render/maplibre_camera.h"
#include "toml_limits.h"

namespace navmap::daemon {

namespace {

// A config is a few KiB; 4 MiB leaves room for any real one and bounds what a wrong file costs.
constexpr FileKind kConfigFile{"config file", std::uint64_t{4} << 20};

std::string where(const std::string& source, const toml::source_region& r) {
    return source + ":" + std::to_string(r.begin.line) + ":" + std::to_string(r.begin.column);
}

// Reads the keys of one table, rejecting unknown ones.
class TableReader {
public:
    TableReader(const toml::table& t, std::string source, std::string prefix, ConfigError* err)
        : m_t(t), m_source(std::move(source)), m_prefix(std::move(prefix)), m_err(err) {}

    template <typename T>
    bool get(const char* key, T& out) {
        m_known.insert(key);
        const toml::node* n = m_t.get(key);
        if (!n) return true;
        if constexpr (std::is_same_v<T, std::string> || std::is_same_v<T, std::filesystem::path>) {
            if (auto v = n->value<std::string>()) {
                out = *v;
                return true;
            }
            return fail(*n, key, "a string");
        } else if constexpr (std::is_same_v<T, bool>) {
            if (auto v = n->value<bool>()) {
                out = *v;
                return true;
            }
            return fail(*n, key, "true or false");
        } else if constexpr (std::is_floating_point_v<T>) {
            if (auto v = n->value<double>()) {
                out = static_cast<T>(*v);
                return true;
            }
            return fail(*n, key, "a number");
        } else {
            if (auto v = n->value<std::int64_t>()) {
                out = static_cast<T>(*v);
                if (static_cast<std::int64_t>(out) != *v || (*v < 0 && std::is_unsigned_v<T>)) {
                    return fail(*n, key, "an integer in range");
                }
                return true;
            }
            return fail(*n, key, "an integer");
        }
    }
    bool range(const char* key, double value, double lo, double hi) {
        if (value >= lo && value <= hi) return true;
        const toml::node* n = m_t.get(key);
        std::ostringstream msg;
        msg << (n ? where(m_source, n->source()) : m_source) << ": " << m_prefix << key << " = " << value
            << " out of range [" << lo << ", " << hi << "]";
        m_err->message = msg.str();
        return false;
    }
    bool noUnknownKeys() {
        for (const auto& [k, v] : m_t) {
            if (!m_known.count(std::string(k.str())) && !v.is_table() && !v.is_array_of_tables()) {
                m_err->message = where(m_source, v.source()) + ": unknown key " + m_prefix + std::string(k.str());
                return false;
            }
        }
        return true;
    }
    void known(const char* key) { m_known.insert(key); }

private:
    bool fail(const toml::node& n, const char* key, const char* expected) {
        m_err->message = where(m_source, n.source()) + ": " + m_prefix + key + " must be " + expected;
        return false;
    }
    const toml::table& m_t;
    std::string m_source, m_prefix;
    ConfigError* m_err;
    std::set<std::string> m_known;
};

// The sections of one config text, each read into a DaemonConfig by its own step; the first
// problem found goes to `err` and ends the parse.
class ConfigParser {
public:
    ConfigParser(const toml::table& root, const std::string& source_name, ConfigError* err)
        : m_root(root), m_source(source_name), m_err(err) {}

    bool knownSections() {
        const std::set<std::string> sections{"store",  "input", "sim", "render",   "profile", "control",
                                             "stream", "log",   "can", "guidance", "style"};
        for (const auto& [k, v] : m_root) {
            if (!sections.count(std::string(k.str()))) {
                m_err->message =
                    where(m_source, v.source()) + ": unknown section or key '" + std::string(k.str()) + "'";
                return false;
            }
        }
        return true;
    }
    bool readStore(DaemonConfig& c);
    bool readInput(DaemonConfig& c);
    void readCan(DaemonConfig& c);
    bool readSim(DaemonConfig& c);
    bool readGuidance(DaemonConfig& c);
    bool readRender(DaemonConfig& c);
    bool readStyle(DaemonConfig& c);
    bool readProfiles(DaemonConfig& c);
    bool readControl(DaemonConfig& c);
    bool readStream(DaemonConfig& c);
    bool readLog(DaemonConfig& c);

private:
    const toml::table* table(const char* name) const {
        const toml::node* n = m_root.get(name);
        return n ? n->as_table() : nullptr;
    }
    TableReader section(const char* name) {
        static const toml::table kEmpty;
        const auto* t = table(name);
        return TableReader(t ? *t : kEmpty, m_source, std::string(name) + ".", m_err);
    }
    bool fileNames(const char* name, const char* key, std::vector<std::filesystem::path>& out);
    bool readIds(const char* section_name, TableReader& r, const char* key, std::vector<std::uint32_t>& out);
    bool readProfile(const toml::node& e, DisplayProfile& p);
    bool readSignCorner(const toml::node& e, const std::string& sign, const std::string& view, DisplayProfile& p);

    const toml::table& m_root;
    const std::string& m_source;
    ConfigError* m_err;
};

// An array of file names (store.mount, input.dbc); anything else in it is an error.
bool ConfigParser::fileNames(const char* name, const char* key, std::vector<std::filesystem::path>& out) {
    const auto* t = table(name);
    const toml::node* n = t ? t->get(key) : nullptr;
    if (!n) return true;
    const toml::array* array = n->as_array();
    if (!array) {  // dbc = "x.dbc" was ignored without a word
        m_err->message = where(m_source, n->source()) + ": " + name + "." + key + " must be an array of file names";
        return false;
    }
    for (const auto& e : *array) {
        if (auto s = e.value<std::string>()) {
            out.emplace_back(*s);
        } else {
            m_err->message = where(m_source, e.source()) + ": " + name + "." + key + " entries must be file names";
            return false;
        }
    }
    return true;
}

// allowed_uids / allowed_gids: arrays of non-negative integers.
bool ConfigParser::readIds(const char* section_name, TableReader& r, const char* key, std::vector<std::uint32_t>& out) {
    r.known(key);
    const auto* t = table(section_name);
    const toml::node* n = t ? t->get(key) : nullptr;
    if (!n) return true;
    const toml::array* arr = n->as_array();
    if (!arr) {
        m_err->message = where(m_source, n->source()) + ": " + section_name + "." + key + " must be an array of ids";
        return false;
    }
    for (const auto& e : *arr) {
        auto v = e.value<std::int64_t>();
        if (!v || *v < 0 || *v > 0xFFFFFFFELL) {
            m_err->message = where(m_source, e.source()) + ": " + section_name + "." + key + " entries must be " +
                             (std::string(key).ends_with("uids") ? "uids" : "gids");
            return false;
        }
        out.push_back(static_cast<std::uint32_t>(*v));
    }
    return true;
}

bool ConfigParser::readStore(DaemonConfig& c) {
    auto r = section("store");
    std::int64_t cache_mb = static_cast<std::int64_t>(c.cache_mb);
    r.known("mount");
    if (!r.get("path", c.store_path) || !r.get("cache_mb", cache_mb) ||
        !r.range("cache_mb", double(cache_mb), 8, 65536) || !r.noUnknownKeys())
        return false;
    c.cache_mb = static_cast<std::size_t>(cache_mb);
    return fileNames("store", "mount", c.mount_paths);
}

bool ConfigParser::readInput(DaemonConfig& c) {
    auto r = section("input");
    std::string source = "sim";
    r.known("dbc");
    if (!r.get("source", source) || !r.get("replay_log", c.replay_log) || !r.get("replay_speed", c.replay_speed) ||
        !r.range("replay_speed", c.replay_speed, 0.01, 1000.0) || !r.get("replay_loop", c.replay_loop) ||
        !r.get("can_interface", c.can_interface) || !r.get("stale_after_s", c.stale_after_s) ||
        !r.range("stale_after_s", c.stale_after_s, 0.05, 600.0) || !r.noUnknownKeys())
        return false;
    if (source == "sim")
        c.input = InputSource::Sim;
    else if (source == "replay")
        c.input = InputSource::Replay;
    else if (source == "socketcan")
        c.input = InputSource::SocketCan;
    else {
        m_err->message = m_source + ": input.source = \"" + source + "\": expected sim, replay or socketcan";
        return false;
    }
    return fileNames("input", "dbc", c.dbc_files);
}

void ConfigParser::readCan(DaemonConfig& c) {
    if (const auto* can = table("can")) {
        // [[can.signal]] tables: handed to ipc::SignalMap as TOML text.
        std::ostringstream s;
        toml::table only;
        only.insert("can", *can);
        s << only;
        c.signal_map_toml = s.str();
    }
}

bool ConfigParser::readSim(DaemonConfig& c) {
    auto r = section("sim");
    return r.get("from", c.sim_from) && r.get("to", c.sim_to) && r.get("speed_factor", c.sim_speed_factor) &&
           r.range("speed_factor", c.sim_speed_factor, 0.01, 1000.0) && r.noUnknownKeys();
}

bool ConfigParser::readGuidance(DaemonConfig& c) {
    auto r = section("guidance");
    GuidanceConfig& g = c.guidance;
    return r.get("off_route_distance_m", g.off_route_distance_m) &&
           r.range("off_route_distance_m", g.off_route_distance_m, 5.0, 1000.0) &&
           r.get("off_route_time_s", g.off_route_time_s) &&
           r.range("off_route_time_s", g.off_route_time_s, 0.0, 600.0) &&
           r.get("on_route_distance_m", g.on_route_distance_m) &&
           r.range("on_route_distance_m", g.on_route_distance_m, 1.0, g.off_route_distance_m - 1.0) &&
           r.get("on_route_time_s", g.on_route_time_s) && r.range("on_route_time_s", g.on_route_time_s, 0.0, 600.0) &&
           r.get("second_arrow_within_m", g.second_arrow_within_m) &&
           r.range("second_arrow_within_m", g.second_arrow_within_m, 0.0, 5000.0) &&
           r.get("lane_distance_m", g.lane_distance_m) && r.range("lane_distance_m", g.lane_distance_m, 0.0, 5000.0) &&
           r.noUnknownKeys();
}

bool ConfigParser::readRender(DaemonConfig& c) {
    auto r = section("render");
    std::string style = "day", ground = "landcover";
    if (!r.get("egl_platform", c.egl_platform) || !r.get("msaa", c.msaa) || !r.range("msaa", c.msaa, -1, 16) ||
        !r.get("style", style) || !r.get("ground", ground) || !r.get("labels", c.labels) ||
        !r.get("gpu_tile_cache", c.gpu_tile_cache) || !r.range("gpu_tile_cache", c.gpu_tile_cache, 0, 100000) ||
        !r.get("shader_cache", c.shader_cache) || !r.noUnknownKeys())
        return false;
    if (c.egl_platform != "auto" && c.egl_platform != "surfaceless" && c.egl_platform != "device") {
        m_err->message =
            m_source + ": render.egl_platform = \"" + c.egl_platform + "\": expected auto, surfaceless or device";
        return false;
    }
    if (style != "day" && style != "night") {
        m_err->message = m_source + ": render.style = \"" + style + "\": expected day or night";
        return false;
    }
    c.night = style == "night";
    if (ground != "landcover" && ground != "orthoimage") {
        m_err->message = m_source + ": render.ground = \"" + ground + "\": expected landcover or orthoimage";
        return false;
    }
    c.orthoimage_ground = ground == "orthoimage";
    return true;
}

// [style]: the mode (render.style's older spelling of a fixed one is read by readRender), where
// auto takes its light from and the thresholds.
bool ConfigParser::readStyle(DaemonConfig& c) {
    auto r = section("style");
    StyleConfig& s = c.style;
    std::string mode, source = "can";
    if (!r.get("mode", mode) || !r.get("source", source) || !r.get("twilight_deg", s.twilight_deg) ||
        !r.range("twilight_deg", s.twilight_deg, -18.0, 10.0) || !r.get("hysteresis_deg", s.hysteresis_deg) ||
        !r.range("hysteresis_deg", s.hysteresis_deg, 0.0, 10.0) ||
        !r.get("light_night_below_pct", s.light_night_below_pct) ||
        !r.range("light_night_below_pct", s.light_night_below_pct, 0.0, 100.0) ||
        !r.get("light_day_above_pct", s.light_day_above_pct) ||
        !r.range("light_day_above_pct", s.light_day_above_pct, s.light_night_below_pct, 100.0) ||
        !r.get("can_timeout_s", s.can_timeout_s) || !r.range("can_timeout_s", s.can_timeout_s, 0.1, 3600.0) ||
        !r.get("fade_s", s.fade_s) || !r.range("fade_s", s.fade_s, 0.0, 60.0) || !r.noUnknownKeys())
        return false;
    if (!mode.empty()) {
        const auto* render = table("render");
        if (render && render->contains("style")) {
            m_err->message = m_source + ": style.mode and render.style both given: keep style.mode";
            return false;
        }
        if (mode != "day" && mode != "night" && mode != "auto") {
            m_err->message = m_source + ": style.mode = \"" + mode + "\": expected day, night or auto";
            return false;
        }
        s.automatic = mode == "auto";
        c.night = mode == "night";
    }
    if (source != "can" && source != "sun") {
        m_err->message = m_source + ": style.source = \"" + source + "\": expected can or sun";
        return false;
    }
    s.prefer_can = source == "can";
    return true;
}

// [[profile]]: the display profiles; none given, the defaults.
bool ConfigParser::readProfiles(DaemonConfig& c) {
    const toml::node* n = m_root.get("profile");
    if (!n) {
        c.profiles = defaultProfiles();
        return true;
    }
    const toml::array* arr = n->as_array();
    if (!arr || !arr->is_array_of_tables()) {
        m_err->message = where(m_source, n->source()) + ": profile must be an array of tables ([[profile]])";
        return false;
    }
    if (arr->size() > kMaxProfiles) {
        m_err->message = where(m_source, (*arr)[kMaxProfiles].source()) + ": " + std::to_string(arr->size()) +
                         " profiles, more than " + std::to_string(kMaxProfiles);
        return false;
    }
    for (const auto& e : *arr) {
        DisplayProfile p;
        if (!readProfile(e, p)) return false;
        c.profiles.push_back(p);
    }
    return true;
}

// profile.speed_limit_sign: a corner or "off"; without it the view decides (none in bird's-eye).
bool ConfigParser::readSignCorner(const toml::node& e, const std::string& sign, const std::string& view,
                                  DisplayProfile& p) {
    static constexpr std::pair<const char*, render::SignCorner> kCorners[] = {
        {"top-left", render::SignCorner::TopLeft},
        {"top-right", render::SignCorner::TopRight},
        {"bottom-left", render::SignCorner::BottomLeft},
        {"bottom-right", render::SignCorner::BottomRight},
    };
    if (!e.as_table()->contains("speed_limit_sign")) {
        p.speed_limit_sign = view == "bird" ? std::nullopt : std::optional(render::SignCorner::TopRight);
        return true;
    }
    if (sign == "off") {
        p.speed_limit_sign.reset();
        return true;
    }
    for (const auto& [name, corner] : kCorners) {
        if (sign == name) {
            p.speed_limit_sign = corner;
            return true;
        }
    }
    m_err->message = where(m_source, e.source()) + ": profile.speed_limit_sign = \"" + sign +
                     "\": expected top-left, top-right, bottom-left, bottom-right or off";
    return false;
}

// One [[profile]] table.
bool ConfigParser::readProfile(const toml::node& e, DisplayProfile& p) {
    TableReader r(*e.as_table(), m_source, "profile.", m_err);
    std::string view = "snail", orientation = "heading-up", roads = "auto", sign;
    double zoom = 0.0, pitch = 0.0;
    if (!r.get("name", p.name) || !r.get("width", p.width) || !r.range("width", p.width, 16, 8192) ||
        !r.get("height", p.height) || !r.range("height", p.height, 16, 8192) || !r.get("fps", p.fps) ||
        !r.range("fps", p.fps, 0.1, 240.0) || !r.get("view", view) || !r.get("orientation", orientation) ||
        !r.get("roads", roads) || !r.get("glow_roads", p.glow_roads) || !r.get("label_aura", p.label_aura) ||
        !r.get("road_selection", p.road_selection) || !r.get("attribution", p.attribution) || !r.get("zoom", zoom) ||
        !r.range("zoom", zoom, render::kMapLibreMinZoom, render::kMapLibreMaxZoom) || !r.get("pitch", pitch) ||
        !r.range("pitch", pitch, render::kMapLibreMinPitchDeg, render::kMapLibreMaxPitchDeg) ||
        !r.get("speed_limit_sign", sign) || !r.get("street_bar", p.street_bar) ||
        !r.get("lane_guidance", p.lane_guidance) || !r.noUnknownKeys())
        return false;
    // A MapLibre GL JS camera needs both; either alone is a mistake, not a default.
    const bool has_zoom = e.as_table()->contains("zoom"), has_pitch = e.as_table()->contains("pitch");
    if (has_zoom != has_pitch) {
        m_err->message = where(m_source, e.source()) + ": profile." + (has_zoom ? "zoom" : "pitch") +
                         " needs profile." + (has_zoom ? "pitch" : "zoom") +
                         " (a MapLibre-convention camera gives both)";
        return false;
    }
    if (has_zoom) p.camera = render::MapLibreFollow{zoom, pitch, std::nullopt};
    if (roads == "geometric")
        p.roads = render::RoadTechnique::Geometric;
    else if (roads == "shadow-volume")
        p.roads = render::RoadTechnique::ShadowVolume;
    else if (roads != "auto") {
        m_err->message = where(m_source, e.source()) + ": profile.roads = \"" + roads +
                         "\": expected geometric, shadow-volume or auto";
        return false;
    }
    if (p.name.empty()) {
        m_err->message = where(m_source, e.source()) + ": profile.name is required";
        return false;
    }
    // Without label_aura the aura follows the view: on where labels lie in the world.
    if (!e.as_table()->contains("label_aura")) p.label_aura = view != "bird";
    // Without attribution it follows the view too: on in bird's-eye (the map display).
    if (!e.as_table()->contains("attribution")) p.attribution = view == "bird";
    if (!readSignCorner(e, sign, view, p)) return false;
    // Without street_bar the view decides: on in snail's views (the cluster) only.
    if (!e.as_table()->contains("street_bar")) p.street_bar = view == "snail";
    // Without lane_guidance the view decides too: the lanes where the driver glances ahead.
    if (!e.as_table()->contains("lane_guidance")) p.lane_guidance = view != "bird";
    if (view == "bird")
        p.view = render::ViewMode::Bird;
    else if (view == "snail")
        p.view = render::ViewMode::Snail;
    else if (view == "hud")
        p.view = render::ViewMode::Snail;  // route-and-manoeuvre style, from behind
    else {
        m_err->message = where(m_source, e.source()) + ": profile.view = \"" + view + "\": expected bird, snail or hud";
        return false;
    }
    if (orientation == "north-up")
        p.orientation = render::Orientation::NorthUp;
    else if (orientation != "heading-up") {
        m_err->message = where(m_source, e.source()) + ": profile.orientation = \"" + orientation +
                         "\": expected heading-up or north-up";
        return false;
    }
    p.stream_view = view;
    return true;
}

bool ConfigParser::readControl(DaemonConfig& c) {
    auto r = section("control");
    std::int64_t mode = c.control_mode;
    if (!r.get("idle_timeout_s", c.control_idle_timeout_s) ||
        !r.range("idle_timeout_s", c.control_idle_timeout_s, 0.0, 86400.0))
        return false;
    if (!r.get("max_clients_per_uid", c.control_max_clients_per_uid) ||
        !r.range("max_clients_per_uid", c.control_max_clients_per_uid, 1, 16) ||
        !r.get("max_subscribers_per_uid", c.control_max_subscribers_per_uid) ||
        !r.range("max_subscribers_per_uid", c.control_max_subscribers_per_uid, 1, 16) ||
        !readIds("control", r, "privileged_uids", c.control_privileged_uids))
        return false;
    if (!readIds("control", r, "allowed_uids", c.control_uids) ||
        !readIds("control", r, "allowed_gids", c.control_gids) || !r.get("socket", c.control_socket) ||
        !r.get("mode", mode) || !r.range("mode", double(mode), 0, 0777) || !r.get("group", c.control_group) ||
        !r.noUnknownKeys())
        return false;
    c.control_mode = static_cast<std::uint32_t>(mode);
    return true;
}

bool ConfigParser::readStream(DaemonConfig& c) {
    auto r = section("stream");
    std::int64_t ring_mb = static_cast<std::int64_t>(c.ring_memory_mb);
    if (!readIds("stream", r, "allowed_uids", c.stream_uids) || !readIds("stream", r, "allowed_gids", c.stream_gids) ||
        !r.get("socket", c.frame_socket) || !r.get("group", c.stream_group) ||
        !r.get("max_clients_per_transport", c.max_clients_per_transport) ||
        !r.range("max_clients_per_transport", c.max_clients_per_transport, 1, 1024) ||
        !r.get("max_clients_per_uid", c.max_clients_per_uid) ||
        !r.range("max_clients_per_uid", c.max_clients_per_uid, 1, 1024) ||
        !r.get("max_clients_per_address", c.max_clients_per_address) ||
        !r.range("max_clients_per_address", c.max_clients_per_address, 1, 1024) || !r.get("ring_memory_mb", ring_mb) ||
        !r.range("ring_memory_mb", double(ring_mb), 1, 65536) || !r.get("handshake_timeout_s", c.handshake_timeout_s) ||
        !r.range("handshake_timeout_s", c.handshake_timeout_s, 0.1, 600.0) || !r.get("tcp_port", c.tcp_port) ||
        !r.range("tcp_port", c.tcp_port, 0, 65535) || !r.get("http_port", c.http_port) ||
        !r.range("http_port", c.http_port, 0, 65535) || !r.get("http_address", c.http_address) ||
        !r.get("http_token", c.http_token) || !r.get("client_timeout_s", c.client_timeout_s) ||
        !r.range("client_timeout_s", c.client_timeout_s, 0.1, 3600.0) || !r.get("stale_pose_ms", c.stale_pose_ms) ||
        !r.range("stale_pose_ms", c.stale_pose_ms, 1, 600000) || !r.noUnknownKeys())
        return false;
    c.ring_memory_mb = static_cast<std::size_t>(ring_mb);
    // The token travels in URLs (?token=): URL-safe characters only, long enough not to guess.
    const bool token_chars = std::all_of(c.http_token.begin(), c.http_token.end(), [](char ch) {
        return (ch >= 'a' && ch <= 'z') || (ch >= 'A' && ch <= 'Z') || (ch >= '0' && ch <= '9') || ch == '-' ||
               ch == '_' || ch == '.' || ch == '~';
    });
    if (!c.http_token.empty() && (c.http_token.size() < 16 || c.http_token.size() > 256 || !token_chars)) {
        m_err->message = m_source + ": stream.http_token must be 16..256 characters of A-Z a-z 0-9 - _ . ~";
        return false;
    }
    return true;
}

bool ConfigParser::readLog(DaemonConfig& c) {
    auto r = section("log");
    std::string level = "info";
    if (!r.get("level", level) || !r.get("watchdog_max_frame_s", c.watchdog_max_frame_s) ||
        !r.range("watchdog_max_frame_s", c.watchdog_max_frame_s, 0.1, 600.0) || !r.noUnknownKeys())
        return false;
    static const std::pair<const char*, int> kLevels[] = {
        {"error", 3}, {"warning", 4}, {"notice", 5}, {"info", 6}, {"debug", 7}};
    bool ok = false;
    for (const auto& [name, prio] : kLevels) {
        if (level == name) {
            c.log_level = prio;
            ok = true;
        }
    }
    if (!ok) {
        m_err->message = m_source + ": log.level = \"" + level + "\": expected error, warning, notice, info or debug";
        return false;
    }
    return true;
}

}  // namespace

std::optional<DaemonConfig> parseConfig(const std::string& text, const std::string& source_name, ConfigError* error) {
    ConfigError local;
    ConfigError* err = error ? error : &local;
    // Before toml++ sees it: depth and size within bounds (toml_limits.h).
    if (std::string limit = checkTomlLimits(text, source_name); !limit.empty()) {
        err->message = std::move(limit);
        return std::nullopt;
    }
    toml::table root;
    try {
        root = toml::parse(text, source_name);
    } catch (const toml::parse_error& e) {
        err->message = where(source_name, e.source()) + ": " + std::string(e.description());
        return std::nullopt;
    }
    DaemonConfig c;
    ConfigParser parser(root, source_name, err);
    if (!parser.knownSections() || !parser.readStore(c) || !parser.readInput(c)) return std::nullopt;
    parser.readCan(c);
    if (!parser.readSim(c) || !parser.readGuidance(c) || !parser.readRender(c) || !parser.readStyle(c) ||
        !parser.readProfiles(c) || !parser.readControl(c) || !parser.readStream(c) || !parser.readLog(c))
        return std::nullopt;
    return c;
}

std::optional<DaemonConfig> loadConfig(const std::filesystem::path& path, ConfigError* error) {
    // Regular files only, opened without blocking, at most kConfigFile.max_bytes read
    // (docs/architecture.md "Untrusted files"): a FIFO or /dev/zero is refused, never waited on.
    std::string problem;
    const std::optional<std::string> text = UntrustedFile::readText(path, kConfigFile, problem);
    if (!text) {
        if (error) error->message = problem;
        return std::nullopt;
    }
    return parseConfig(*text, path.string(), error);
}

bool validateConfig(const DaemonConfig& c, ConfigError* error) {
    auto fail = [&](std::string m) {
        if (error) error->message = std::move(m);
        return false;
    };
    if (c.profiles.empty()) return fail("no display profile configured");
    std::set<std::string> names;
    for (const auto& p : c.profiles) {
        if (!names.insert(p.name).second) return fail("profile '" + p.name + "' defined twice");
    }
    if (c.input == InputSource::Replay && c.replay_log.empty())
        return fail("input.source = \"replay\" needs input.replay_log");
    if (c.input == InputSource::SocketCan && c.can_interface.empty())
        return fail("input.source = \"socketcan\" needs input.can_interface");
    if (c.store_path.empty()) return fail("store.path is empty");
    return true;
}

std::string describeConfig(const DaemonConfig& c) {
    std::ostringstream s;
    s << "store: " << c.store_path.string() << " (cache " << c.cache_mb << " MiB)\n";
    for (const auto& m : c.mount_paths) s << "mounted: " << m.string() << "\n";
    s << "input: "
      << (c.input == InputSource::Sim      ? "sim " + c.sim_from + " -> " + c.sim_to
          : c.input == InputSource::Replay ? "replay " + c.replay_log.string()
                                           : "socketcan " + c.can_interface)
      << ", position stale after " << c.stale_after_s << " s\n";
    s << "render: egl " << c.egl_platform << ", msaa " << c.msaa << ", style "
      << (c.style.automatic ? (c.style.prefer_can ? "auto (CAN light signal, else the sun)" : "auto (the sun)")
          : c.night         ? "night"
                            : "day")
      << ", ground " << (c.orthoimage_ground ? "orthoimage" : "landcover") << ", labels " << (c.labels ? "on" : "off")
      << ", gpu tile cache " << (c.gpu_tile_cache > 0 ? std::to_string(c.gpu_tile_cache) : std::string("auto"))
      << ", shader cache "
      << (c.shader_cache.empty() ? std::string("$CACHE_DIRECTORY or none") : c.shader_cache.string()) << "\n";
    for (const auto& p : c.profiles) {
        s << "profile " << p.name << ": " << p.width << "x" << p.height << " @ " << p.fps << " fps, "
          << (p.view == render::ViewMode::Bird ? "bird" : "snail") << ", "
          << (p.orientation == render::Orientation::NorthUp ? "north-up" : "heading-up") << ", roads "
          << (p.roads == render::RoadTechnique::Geometric      ? "geometric"
              : p.roads == render::RoadTechnique::ShadowVolume ? "shadow-volume"
                                                               : "auto")
          << (p.glow_roads ? ", glowing roads" : "") << (p.label_aura ? ", label aura" : "")
          << (p.road_selection ? "" : ", every road class at every distance") << (p.attribution ? ", attribution" : "");
        if (p.camera) s << ", MapLibre camera zoom " << p.camera->zoom << " pitch " << p.camera->pitch_deg;
        s << "\n";
    }
    const auto ids = [](const std::vector<std::uint32_t>& v) {
        std::string out;
        for (const auto id : v) out += (out.empty() ? "" : ",") + std::to_string(id);
        return out;
    };
    s << "control: " << c.control_socket.string() << " (mode " << std::oct << c.control_mode << std::dec
      << (c.control_group.empty() ? "" : ", group " + c.control_group) << ", uids "
      << (c.control_uids.empty() ? "own" : ids(c.control_uids))
      << (c.control_gids.empty() ? "" : ", gids " + ids(c.control_gids)) << ")\n";
    s << "control limits: " << c.control_max_clients_per_uid << " clients and " << c.control_max_subscribers_per_uid
      << " subscribers per unprivileged uid; privileged: root, own"
      << (c.control_privileged_uids.empty() ? "" : "," + ids(c.control_privileged_uids)) << "\n";
    s << "stream: " << c.frame_socket.string() << " (mode 660"
      << (c.stream_group.empty() ? "" : ", group " + c.stream_group) << ", uids "
      << (c.stream_uids.empty() ? "own" : ids(c.stream_uids))
      << (c.stream_gids.empty() ? "" : ", gids " + ids(c.stream_gids)) << "), tcp " << c.tcp_port << ", http "
      << (c.http_port > 0
              ? c.http_address + ":" + std::to_string(c.http_port) + (c.http_token.empty() ? "" : " (token)")
              : std::string("off"))
      << "\n";
    s << "stream limits: " << c.max_clients_per_transport << " clients per transport, " << c.max_clients_per_uid
      << " per uid, " << c.max_clients_per_address << " per TCP/HTTP address, ring memory " << c.ring_memory_mb
      << " MiB, handshake and first frame within " << c.handshake_timeout_s << " s, frames stale_pose after "
      << c.stale_pose_ms << " ms without a fix\n";
    return s.str();
}

}  // namespace navmap::daemon
