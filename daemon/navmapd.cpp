// SPDX-License-Identifier: Apache-2.0
// navmapd: the navigation-map renderer daemon. Reads its TOML configuration (optional; every key
// has a default, docs/navmapd.md), applies command-line overrides and runs the main loop
// (daemon.h) until SIGTERM. `--check-config` validates and prints the effective configuration.
// Exit status: 0 ok, 1 bad configuration or a failure at run time, 2 usage (docs/tools.md).
// It hands the drive simulator to the daemon (RunOptions::simulator): the daemon's library
// (navmap_daemon_core) neither includes nor links sim/.

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>

#include "config.h"
#include "daemon.h"
#include "navmap/cli/cli.h"
#include "navmap/install_layout.h"
#include "navmap/sim/simulated_can_source.h"
#include "vehicle_input.h"

namespace {

// "2024-12-21T09:20:00Z" -> that instant; none when it is no such time.
std::optional<std::chrono::system_clock::time_point> parseUtcTime(const std::string& text) {
    int y = 0, mo = 0, d = 0, h = 0, mi = 0, s = 0;
    char z = 0;
    int used = 0;
    if (std::sscanf(text.c_str(), "%4d-%2d-%2dT%2d:%2d:%2d%c%n", &y, &mo, &d, &h, &mi, &s, &z, &used) != 7 ||
        z != 'Z' || used != static_cast<int>(text.size()) || h > 23 || mi > 59 || s > 59)
        return std::nullopt;
    const std::chrono::year_month_day day{std::chrono::year(y), std::chrono::month(unsigned(mo)),
                                          std::chrono::day(unsigned(d))};
    if (!day.ok()) return std::nullopt;
    return std::chrono::sys_days(day) + std::chrono::hours(h) + std::chrono::minutes(mi) + std::chrono::seconds(s);
}

}  // namespace

int main(int argc, char** argv) {
    using namespace navmap::daemon;
    CLI::App app{"navmapd - headless 3D navigation-map renderer daemon"};
    navmap::cli::setUp(app, "navmapd");
    std::string config_path, store, input, replay, can_iface, from, to, control_socket, frame_socket, style, egl,
        log_level, shader_cache, sun_time;
    std::vector<std::string> profile_names;
    std::optional<double> speed, run_for;
    std::optional<int> http_port, tcp_port, msaa;
    bool check = false, render_all = false, noop = false, no_labels = false;
    app.add_option("-c,--config", config_path, "TOML configuration file (defaults apply without one)");
    app.add_flag("--check-config", check, "validate the configuration, print it and exit");
    app.add_option("--store", store,
                   "compiled tile store (navmap-compile); default: " + navmap::install::defaultStore().string());
    std::vector<std::string> mounts;
    app.add_option("--mount", mounts, "another store drawn with it (repeat for more; added to store.mount)");
    app.add_option("--input", input, "vehicle input: sim | replay | socketcan")
        ->check(CLI::IsMember({"sim", "replay", "socketcan"}));
    app.add_option("--replay", replay, "candump log to replay (implies --input replay)");
    app.add_option("--can-interface", can_iface, "SocketCAN interface (implies --input socketcan)");
    app.add_option("--from", from, "simulated drive start: lat,lon or a place name");
    app.add_option("--to", to, "simulated drive destination");
    app.add_option("--speed", speed, "replay / simulation speed factor")->check(navmap::cli::finiteIn(0.01, 1000.0));
    app.add_option("--profiles", profile_names, "render only these profiles (cluster,hud,center)")->delimiter(',');
    app.add_option("--control-socket", control_socket, "control socket path");
    app.add_option("--frame-socket", frame_socket, "frame-stream socket path");
    app.add_option("--http-port", http_port, "HTTP port (MJPEG, status page, /metrics); 0 = off")
        ->check(navmap::cli::integerIn(0, 65535));
    app.add_option("--tcp-port", tcp_port, "TCP frame-stream port; 0 = off")->check(navmap::cli::integerIn(0, 65535));
    app.add_option("--style", style, "day | night | auto (style.mode)")->check(CLI::IsMember({"day", "night", "auto"}));
    app.add_option("--sun-time", sun_time,
                   "auto style: the sun as at this UTC time at start (YYYY-MM-DDTHH:MM:SSZ), running on from there");
    app.add_option("--egl-platform", egl, "auto | surfaceless | device")
        ->check(CLI::IsMember({"auto", "surfaceless", "device"}));
    app.add_option("--msaa", msaa, "MSAA samples (0 off, -1 auto)")->check(navmap::cli::integerIn(-1, 16));
    app.add_option("--log-level", log_level, "error | warning | notice | info | debug")
        ->check(CLI::IsMember({"error", "warning", "notice", "info", "debug"}));
    app.add_option("--run-for", run_for, "stop after this many seconds")->check(navmap::cli::finiteIn(0.1, 1e7));
    app.add_flag("--render-all", render_all, "render every profile even without clients");
    app.add_flag("--no-labels", no_labels, "draw no labels");
    app.add_option("--shader-cache", shader_cache, "shader cache directory (render.shader_cache)");
    app.add_flag("--noop", noop, "no GL: the no-op renderer (testing the loop)");
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) return *exit_status;

    ConfigError err;
    std::optional<DaemonConfig> config =
        config_path.empty() ? parseConfig("", "<defaults>", &err) : loadConfig(config_path, &err);
    if (!config) {
        std::fprintf(stderr, "<3>navmapd: %s\n", err.message.c_str());
        return 1;
    }
    DaemonConfig& c = *config;
    if (c.store_path.empty()) c.store_path = navmap::install::defaultStore();
    if (!store.empty()) c.store_path = store;
    for (const auto& m : mounts) c.mount_paths.emplace_back(m);
    if (!input.empty())
        c.input = input == "sim" ? InputSource::Sim : input == "replay" ? InputSource::Replay : InputSource::SocketCan;
    if (!replay.empty()) c.replay_log = replay, c.input = InputSource::Replay;
    if (!can_iface.empty()) c.can_interface = can_iface, c.input = InputSource::SocketCan;
    if (!from.empty()) c.sim_from = from;
    if (!to.empty()) c.sim_to = to;
    if (speed) c.replay_speed = c.sim_speed_factor = *speed;
    if (!control_socket.empty()) c.control_socket = control_socket;
    if (!frame_socket.empty()) c.frame_socket = frame_socket;
    if (http_port) c.http_port = *http_port;
    if (tcp_port) c.tcp_port = *tcp_port;
    if (!style.empty()) {
        c.style.automatic = style == "auto";
        c.night = style == "night";
    }
    std::optional<std::chrono::system_clock::time_point> sun_start;
    if (!sun_time.empty()) {
        sun_start = parseUtcTime(sun_time);
        if (!sun_start) {
            std::fprintf(stderr, "<3>navmapd: --sun-time %s: expected YYYY-MM-DDTHH:MM:SSZ\n", sun_time.c_str());
            return 2;
        }
    }
    if (!egl.empty()) c.egl_platform = egl;
    if (msaa) c.msaa = *msaa;
    if (no_labels) c.labels = false;
    if (!shader_cache.empty()) c.shader_cache = shader_cache;
    if (!log_level.empty()) {
        const std::string& l = log_level;
        c.log_level = l == "error" ? 3 : l == "warning" ? 4 : l == "notice" ? 5 : l == "info" ? 6 : 7;
    }
    if (!profile_names.empty()) {
        std::vector<DisplayProfile> chosen;
        for (const auto& name : profile_names) {
            auto p = findProfile(c.profiles, name);
            if (!p) {
                std::fprintf(stderr, "<3>navmapd: --profiles: unknown profile '%s'\n", name.c_str());
                return 1;
            }
            chosen.push_back(*p);
        }
        c.profiles = chosen;
    }
    if (!validateConfig(c, &err)) {
        std::fprintf(stderr, "<3>navmapd: %s\n", err.message.c_str());
        return 1;
    }
    if (check) {
        // The DBC files and the signal map, as the start opens them: their errors are
        // configuration errors too (exit 1), not something to find out at the start.
        DecoderSetup setup;
        try {
            (void)VehicleInput::openDecoder(c, navmap::install::dataDir(), &setup);
        } catch (const std::exception& e) {
            std::fprintf(stderr, "<3>navmapd: %s\n", e.what());
            return 1;
        }
        for (const auto& w : setup.warnings) std::fprintf(stderr, "<4>navmapd: %s\n", w.c_str());
        std::cout << "configuration OK\n" << describeConfig(c);
        return 0;
    }
    // The shader caches (docs/navmapd.md "Start-up"), set before any thread or EGL display
    // exists: Mesa reads MESA_SHADER_CACHE_DIR when the display is initialised. An explicit
    // MESA_SHADER_CACHE_DIR in the environment stays.
    if (c.shader_cache.empty()) {
        if (const char* dirs = std::getenv("CACHE_DIRECTORY"); dirs && *dirs) {
            const std::string first(dirs, std::strcspn(dirs, ":"));  // systemd lists several with ':'
            c.shader_cache = first;
        }
    }
    if (!c.shader_cache.empty()) {
        // Mesa makes only the last directory of the path: the rest must exist.
        std::error_code ec;
        std::filesystem::create_directories(c.shader_cache / "mesa", ec);
        ::setenv("MESA_SHADER_CACHE_DIR", (c.shader_cache / "mesa").c_str(), 0);
    }
    RunOptions options;
    options.run_for_s = run_for;
    if (!config_path.empty()) options.config_path = config_path;
    options.data_dir = navmap::install::dataDir();
    options.noop_renderer = noop;
    options.render_all_profiles = render_all;
    if (sun_start) {
        const auto started = std::chrono::steady_clock::now();
        options.wall_clock = [started, at = *sun_start] {
            return at + std::chrono::duration_cast<std::chrono::system_clock::duration>(
                            std::chrono::steady_clock::now() - started);
        };
    }
    // The composition root: the only place in daemon/ that names the simulator.
    options.simulator = navmap::sim::openSimulatedDrive;
    return runDaemon(std::move(c), options);
}
