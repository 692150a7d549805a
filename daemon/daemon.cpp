// SPDX-License-Identifier: Apache-2.0
#include "daemon.h"

#include <set>
#include <stdexcept>

#include "config_reloader.h"
#include "daemon_metrics.h"
#include "daemon_status.h"
#include "display_scheduler.h"
#include "lifecycle.h"
#include "log.h"
#include "navmap/ipc/control_server.h"
#include "navmap/ipc/control_state.h"
#include "navmap/ipc/frame_server.h"
#include "navmap/map/map_scene.h"
#include "navmap/version.h"
#include "pose_events.h"
#include "pose_source.h"
#include "route_guidance.h"
#include "route_state.h"
#include "server_options.h"
#include "status_reporter.h"
#include "vehicle_input.h"

namespace navmap::daemon {

namespace {

using Clock = std::chrono::steady_clock;

map::MapScene openScene(const DaemonConfig& config, const Log& log) {
    std::vector<std::filesystem::path> paths{config.store_path};
    paths.insert(paths.end(), config.mount_paths.begin(), config.mount_paths.end());
    map::MapScene scene = map::MapScene::open(paths, config.cache_mb << 20);
    log(Log::kInfo, "store %s: %u tiles, cache %zu MiB", config.store_path.c_str(), scene.store->info().tile_count,
        config.cache_mb);
    if (scene.set) {
        for (std::size_t i = 1; i < scene.set->storeCount(); ++i) {
            const map::TileStore& s = scene.set->store(i);
            log(Log::kInfo, "mounted store %s: %u tiles under world tile %s", s.path().c_str(), s.info().tile_count,
                s.scheme().worldRoot().toString().c_str());
        }
    }
    // A damaged road graph degrades like a damaged tile: the map renders, what needs the graph
    // says it is missing (docs/tile-store.md "Damage").
    if (!scene.graph_problem.empty()) {
        log(Log::kWarning, "%s; map matching is off (the pose is the raw fix) and the simulator cannot plan a route",
            scene.graph_error.c_str());
    }
    return scene;
}

std::shared_ptr<ipc::ControlState> makeControlState(const DaemonConfig& config) {
    std::set<std::string, std::less<>> display_names;
    for (const auto& p : config.profiles) display_names.insert(p.name);
    auto control = std::make_shared<ipc::ControlState>(display_names);
    ipc::SetStyleCommand style;
    style.style = config.night ? ipc::MapStyle::Night : ipc::MapStyle::Day;
    style.ground = config.orthoimage_ground ? ipc::Ground::Orthoimage : ipc::Ground::LandCover;
    (void)control->setStyle(style);
    return control;
}

std::unique_ptr<ipc::ControlServer> createControlServer(const DaemonConfig& config, ipc::ControlState& state) {
    auto control = ipc::ControlServer::create(controlServerConfig(config), state);
    if (!control) throw std::runtime_error(control.error().message);
    return std::move(control).value();
}

// Listening from here on; /metrics and /status show the daemon's latest snapshots.
std::unique_ptr<ipc::FrameServer> startFrameServer(const DaemonConfig& config, const DaemonMetrics& metrics,
                                                   const DaemonStatus& status) {
    ipc::FrameServerOptions fopt = frameServerOptions(config);
    fopt.metrics = [&metrics](ipc::MetricsRegistry& registry) { metrics.registerInto(registry); };
    fopt.status_json = [&status] { return status.text(); };
    auto frames = std::make_unique<ipc::FrameServer>(fopt);
    if (auto st = frames->start(); !st) throw std::runtime_error(st.message());
    return frames;
}

void announceReady(const Log& log, SystemdNotifier& systemd, const DaemonConfig& config, const ipc::FrameServer& frames,
                   const VehicleInput& input, std::size_t displays, Clock::time_point started) {
    std::string endpoints = "control " + config.control_socket.string() + ", frames " + config.frame_socket.string();
    if (frames.httpPort() > 0)
        endpoints += ", http://" + config.http_address + ":" + std::to_string(frames.httpPort()) + "/";
    if (frames.tcpPort() > 0) endpoints += ", tcp " + std::to_string(frames.tcpPort());
    log(Log::kNotice, "ready in %.0f ms: %s; input %s; navmap %s",
        std::chrono::duration<double, std::milli>(Clock::now() - started).count(), endpoints.c_str(),
        input.stats().source.c_str(), NAVMAP_VERSION);
    systemd.ready("rendering " + std::to_string(displays) + " profiles; " + endpoints);
}

// The route of the control socket's newest snapshot: converted once, then handed to the estimator
// and the guidance.
void followRoute(RouteState& route, RouteGuidance& guidance, const ipc::ControlState& control, VehicleInput& input,
                 const Log& log) {
    const auto snapshot = control.route();
    if (!route.update(snapshot)) return;
    input.setRoute(route.line());
    guidance.setRoute(snapshot);
    if (route.id().empty())
        log(Log::kInfo, "route cleared");
    else
        log(Log::kInfo, "route %s: %zu points, %.1f km, %zu maneuvers", route.id().c_str(), route.controlPoints(),
            route.lengthM() / 1000.0, guidance.route() ? guidance.route()->maneuvers().size() : std::size_t{0});
}

FrameContext frameContext(const ipc::ViewState* view, const RouteState& route, const RouteGuidance& guidance,
                          bool labels) {
    FrameContext c;
    c.view_state = view;
    c.style = view && view->style == ipc::MapStyle::Night ? render::MapStyle::night() : render::MapStyle::day();
    c.style.ground =
        view && view->ground == ipc::Ground::Orthoimage ? render::Ground::Orthoimage : render::Ground::LandCover;
    c.route = route.geometry();  // each renderer drapes it onto the tiles it draws: no per-tick heights
    c.route_progress_m = route.drivenM();
    c.guidance = &guidance.snapshot();
    c.labels = labels;
    return c;
}

}  // namespace

int runDaemon(DaemonConfig config, const RunOptions& options) {
    const Log log{config.log_level};
    const auto t_start = Clock::now();
    SystemdNotifier systemd;
    try {
        Signals signals;
        if (ConfigError err; !validateConfig(config, &err)) throw std::runtime_error("config: " + err.message);
        map::MapScene scene = openScene(config, log);
        const std::string road_graph = scene.graph_problem.empty() ? "ok" : "unavailable: " + scene.graph_problem;
        const auto control_state = makeControlState(config);
        DaemonStatus status;
        DaemonMetrics metrics;
        control_state->setStatusProvider([&status] { return status.json(); });
        // The map matcher is the road graph's only user here: it takes the scene's copy (1.6 MB).
        VehicleInput input(config, scene.projection(), scene.store->path(), scene.graph_problem,
                           std::make_shared<const map::RoadGraph>(std::move(scene.graph)), control_state,
                           options.data_dir, options.simulator, scene.reachM());
        const auto control_server = createControlServer(config, *control_state);
        const auto frames = startFrameServer(config, metrics, status);
        DisplayScheduler displays(
            config,
            {options.noop_renderer, options.render_all_profiles,
             options.data_dir.empty() ? std::filesystem::path() : options.data_dir / "ortho-mlp.nnw"},
            scene.cache, scene.projection(), *frames, t_start, log);
        input.start();
        if (auto st = control_server->start(); !st) throw std::runtime_error(st.message());
        announceReady(log, systemd, config, *frames, input, displays.displays().size(), t_start);

        const auto& info = scene.store->info();
        const PoseSource poses([&input] { return input.state(); }, scene.cache,
                               scene.toPlanar((info.south + info.north) / 2, (info.west + info.east) / 2));
        RouteState route(scene.projection());
        PoseEvents events(*control_server, log);
        RouteGuidance guidance(
            scene.projection(), config.guidance,
            [&server = *control_server](const ipc::ControlEvent& e) { server.publish(e); }, log);
        ConfigReloader reloader(config, options.config_path, log);
        StatusReporter reporter(
            {config, reloader, input, road_graph, route, displays, *frames, *control_server, *scene.cache, scene},
            status, metrics, systemd, t_start);
        for (bool stop = false; !stop;) {
            const auto now = Clock::now();
            if (options.run_for_s && std::chrono::duration<double>(now - t_start).count() >= *options.run_for_s) break;
            const EstimatedPose pose = input.state()->poseAt(ipc::CanClock::now());
            const auto view_state = control_state->view();
            followRoute(route, guidance, *control_state, input, log);
            route.track(pose);
            guidance.update(pose, std::chrono::duration<double>(now - t_start).count());
            events.update(pose, route, now);
            const auto next_wake =
                displays.tick(now, poses, frameContext(view_state.get(), route, guidance, config.labels));
            // Health: WATCHDOG=1 only while frames keep completing (or nobody needs any).
            if (displays.framesFlowing(config.watchdog_max_frame_s)) systemd.watchdog();
            reporter.update(now, pose);
            const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_wake - Clock::now());
            switch (signals.wait(std::max(wait, std::chrono::milliseconds(0)))) {
                case SignalEvent::Stop: stop = true; break;
                case SignalEvent::Reload:
                    systemd.reloading();
                    reloader.reload(*control_state, displays);
                    systemd.ready("reloaded");
                    reporter.refresh();  // status and metrics show the reload at once
                    break;
                case SignalEvent::None: break;
            }
        }
        log(Log::kNotice, "stopping");
        systemd.stopping();
        control_server->stop();
        input.stop();
        frames->stop();  // closes every client connection: they see the stream end
        displays.logSummary();
        return 0;
    } catch (const std::exception& e) {
        log(Log::kErr, "%s", e.what());
        return 1;
    }
}

}  // namespace navmap::daemon
