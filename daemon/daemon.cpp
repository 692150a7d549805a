// SPDX-License-Identifier: Apache-2.0
#include "daemon.h"

#include <future>
#include <memory>
#include <mutex>
#include <set>
#include <stdexcept>

#include "config_reloader.h"
#include "daemon_metrics.h"
#include "daemon_status.h"
#include "day_night.h"
#include "display_scheduler.h"
#include "frame_recentring.h"
#include "lifecycle.h"
#include "log.h"
#include "navmap/ipc/control/control_server.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/map/map_scene.h"
#include "navmap/map/store_set.h"
#include "navmap/version.h"
#include "pose_events.h"
#include "pose_source.h"
#include "process_clock.h"
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
    // Map matching snaps onto the roads of every store: the mounted stores' graphs follow the
    // first one's in its frame (the simulator plans on the first store only).
    for (std::size_t i = 1; scene.set && i < scene.set->storeCount(); ++i) {
        const map::TileStore& s = scene.set->store(i);
        auto graph = s.tryLoadGraph();
        if (!graph.problem.empty()) {
            log(Log::kWarning, "%s; map matching is off on this store's roads", graph.error.c_str());
            continue;
        }
        map::appendRoadGraph(scene.graph, graph.graph, scene.projection().transformFrom(s.projection()));
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
    style.style = configuredStyle(config);
    style.configured = true;
    style.ground = config.orthoimage_ground ? ipc::Ground::Orthoimage : ipc::Ground::LandCover;
    (void)control->setStyle(style);
    return control;
}

std::unique_ptr<ipc::ControlServer> createControlServer(const DaemonConfig& config, ipc::ControlState& state) {
    auto control = ipc::ControlServer::create(controlServerConfig(config), state);
    if (!control) throw std::runtime_error(control.error().message);
    return std::move(control).value();
}

// Why dma-buf frames are refused, for the frame server's thread: the renderer's probe once it is up
// (the server listens before the renderer exists).
class DmabufRefusal {
public:
    void set(std::string why) {
        const std::lock_guard lock(m_mutex);
        m_why = std::move(why);
    }
    std::string text() const {
        const std::lock_guard lock(m_mutex);
        return m_why;
    }

private:
    mutable std::mutex m_mutex;
    std::string m_why = "the renderer is still starting";
};

// Listening from here on; /metrics and /status show the daemon's latest snapshots.
std::unique_ptr<ipc::FrameServer> startFrameServer(const DaemonConfig& config, const DaemonMetrics& metrics,
                                                   const DaemonStatus& status, const DmabufRefusal& dmabuf) {
    ipc::FrameServerOptions fopt = frameServerOptions(config);
    fopt.metrics = [&metrics](ipc::MetricsRegistry& registry) { metrics.registerInto(registry); };
    fopt.status_json = [&status] { return status.text(); };
    fopt.dmabuf_unavailable_reason = [&dmabuf] { return dmabuf.text(); };
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

// What keeps positions in the map frame, for re-centring it.
struct FrameParts {
    map::MapScene& scene;
    std::shared_ptr<const map::RoadGraph> graph;  // every store's roads, in graph_frame
    map::Projection graph_frame;
    VehicleInput& input;
    RouteState& route;
    RouteGuidance& guidance;
    DisplayScheduler& displays;
    PoseSource& poses;
};

// Re-centres the map frame on `next` (FrameRecentring::due): the tiles come again from the stores
// re-expressed into it (those drawn last are loaded before this returns), and the estimator, the
// route, the guidance and the displays move into it.
void recentre(FrameRecentring& frames, const map::Projection& next, double scale_error, FrameParts& p, const Log& log) {
    const auto start = Clock::now();
    const map::FrameTransform to_next = frames.adopt(next);
    p.scene.set = p.scene.set ? p.scene.set->inFrame(next) : map::StoreSet::mount({p.scene.store}, next);
    const std::size_t tiles = p.scene.cache->replaceSource(p.scene.set);
    FrameRebase rebase;
    rebase.epoch = frames.epoch();
    rebase.frame = next;
    rebase.to_frame = to_next;
    rebase.graph = p.graph;
    rebase.graph_to_frame = next.transformFrom(p.graph_frame);
    rebase.max_distance_from_origin_m = VehicleStateConfig{}.max_distance_from_origin_m + p.scene.reachM(next);
    p.route.rebase(next);
    p.guidance.rebase(next);
    p.input.rebase(rebase, p.route.line());
    p.displays.rebase(next);
    p.poses.rebase(to_next);
    log(Log::kNotice,
        "map frame re-centred on %.5f, %.5f (scale error there was %+.2f %%): %zu tiles reloaded in %.0f ms",
        next.originLat(), next.originLon(), scale_error * 100.0, tiles,
        std::chrono::duration<double, std::milli>(Clock::now() - start).count());
}

// What DayNight decides this tick's style from: the vehicle's place (the map's centre before the
// first fix), the time of day there, the light signals.
DayNightInput dayNightInput(const ipc::ViewState& view, const EstimatedPose& pose, const FrameRecentring& frame,
                            const map::MapScene& scene, const VehicleInput& input, const RunOptions& options,
                            double now_s) {
    DayNightInput in;
    in.requested = view.style;
    in.requested_by_hmi = view.style_from_hmi;
    in.in_tunnel = pose.valid && pose.in_tunnel;
    if (pose.valid) {
        frame.frame().reverse({pose.x, pose.y}, in.lat_deg, in.lon_deg);
    } else {
        const auto& info = scene.store->info();
        in.lat_deg = (info.south + info.north) / 2;
        in.lon_deg = (info.west + info.east) / 2;
    }
    in.wall_time = options.wall_clock ? options.wall_clock() : std::chrono::system_clock::now();
    in.light = *input.ambientLight();
    in.can_now = ipc::CanClock::now();
    in.now_s = now_s;
    return in;
}

FrameContext frameContext(const ipc::ViewState* view, const render::MapStyle& style, const RouteState& route,
                          const RouteGuidance& guidance, bool labels, FrameHealth health) {
    FrameContext c;
    c.view_state = view;
    c.style = style;
    c.style.ground =
        view && view->ground == ipc::Ground::Orthoimage ? render::Ground::Orthoimage : render::Ground::LandCover;
    c.route = route.geometry();  // each renderer drapes it onto the tiles it draws: no per-tick heights
    c.route_progress_m = route.drivenM();
    c.guidance = &guidance.snapshot();
    c.labels = labels;
    c.health = health;
    return c;
}

}  // namespace

int runDaemon(DaemonConfig config, const RunOptions& options) {
    const Log log{config.log_level};
    const auto t_start = Clock::now();
    const auto t_exec = processStartTime(t_start);
    // Start-up stages, timed from the exec (docs/navmapd.md "Start-up").
    const auto stage = [&log, t_exec](const char* what) {
        log(Log::kInfo, "start-up: %s at %.0f ms", what,
            std::chrono::duration<double, std::milli>(Clock::now() - t_exec).count());
    };
    stage("main");
    SystemdNotifier systemd;
    try {
        Signals signals;
        if (ConfigError err; !validateConfig(config, &err)) throw std::runtime_error("config: " + err.message);
        map::MapScene scene = openScene(config, log);
        stage("store open");
        const std::string road_graph = scene.graph_problem.empty() ? "ok" : "unavailable: " + scene.graph_problem;
        const auto control_state = makeControlState(config);
        DaemonStatus status;
        DaemonMetrics metrics;
        DmabufRefusal dmabuf_refusal;  // outlives the frame server that asks it
        control_state->setStatusProvider([&status] { return status.json(); });
        // The map matcher is the road graph's only user here: it takes the scene's copy (1.6 MB per
        // store), kept in the first store's frame for re-centring.
        const auto graph = std::make_shared<const map::RoadGraph>(std::move(scene.graph));
        // The vehicle input is made (the simulator plans its route: ~100 ms) and started on another
        // thread while this one makes the renderer (EGL, programs, the driver's first shader code:
        // ~350 ms on llvmpipe); the two share nothing but the thread-safe control state. Positions
        // flow while the renderer is made: the first frames have a pose to aim at.
        auto input_made = std::async(std::launch::async, [&] {
            auto made = std::make_unique<VehicleInput>(config, scene.projection(), scene.store->path(),
                                                       scene.graph_problem, graph, control_state, options.data_dir,
                                                       options.simulator, scene.reachM());
            made->start();
            return made;
        });
        const auto control_server = createControlServer(config, *control_state);
        const auto frames = startFrameServer(config, metrics, status, dmabuf_refusal);
        DisplayScheduler displays(
            config,
            {options.noop_renderer, options.render_all_profiles,
             options.data_dir.empty() ? std::filesystem::path() : options.data_dir / "ortho-mlp.nnw", t_exec},
            scene.cache, scene.projection(), *frames, t_start, log);
        dmabuf_refusal.set(DisplayScheduler::dmabufRefusal(displays.dmabuf()));
        stage("renderer and targets");
        const std::unique_ptr<VehicleInput> input_owner = input_made.get();
        VehicleInput& input = *input_owner;
        for (const auto& w : input.setupWarnings()) log(Log::kWarning, "%s", w.c_str());
        stage("vehicle input");
        if (auto st = control_server->start(); !st) throw std::runtime_error(st.message());
        announceReady(log, systemd, config, *frames, input, displays.displays().size(), t_start);

        const auto& info = scene.store->info();
        PoseSource poses([&input](ipc::CanTime t) { return input.poseAt(t); }, scene.cache,
                         scene.toPlanar((info.south + info.north) / 2, (info.west + info.east) / 2));
        RouteState route(scene.projection(), RouteState::TunnelGraph{graph, scene.projection()});
        PoseEvents events(*control_server, log);
        RouteGuidance guidance(
            scene.projection(), config.guidance,
            [&server = *control_server](const ipc::ControlEvent& e) { server.publish(e); }, log);
        if (scene.graph_problem.empty()) guidance.setGraph(graph, scene.projection());  // lanes (docs/guidance.md)
        ConfigReloader reloader(config, options.config_path, log);
        FrameRecentring frame(scene.projection());
        FrameParts frame_parts{scene, graph, scene.projection(), input, route, guidance, displays, poses};
        DayNight day_night(config.style);
        StatusReporter reporter({config, reloader, input, road_graph, route, displays, *frames, *control_server,
                                 *scene.cache, scene, frame, day_night},
                                status, metrics, systemd, t_start);
        int gpu_resets_told = 0;
        for (bool stop = false; !stop;) {
            const auto now = Clock::now();
            if (options.run_for_s && std::chrono::duration<double>(now - t_start).count() >= *options.run_for_s) break;
            EstimatedPose pose = input.poseAt(ipc::CanClock::now());
            if (const auto next =
                    pose.valid && !pose.stale && !input.rebasePending() ? frame.due(pose.x, pose.y) : std::nullopt) {
                recentre(frame, *next, FrameRecentring::scaleError(frame.frame(), pose.x, pose.y), frame_parts, log);
                pose = input.poseAt(pose.time);
            }
            const auto view_state = control_state->view();
            followRoute(route, guidance, *control_state, input, log);
            route.track(pose);
            guidance.update(pose, std::chrono::duration<double>(now - t_start).count());
            events.update(pose, route, now);
            const render::MapStyle style = day_night.update(dayNightInput(
                *view_state, pose, frame, scene, input, options, std::chrono::duration<double>(now - t_start).count()));
            // What each frame says about itself (docs/frame-protocol.md "Frame validity").
            FrameHealth health;
            health.stale_pose_ms = config.stale_pose_ms;
            health.road_graph_off = !scene.graph_problem.empty();
            health.orthoimage_off =
                view_state && view_state->ground == ipc::Ground::Orthoimage && !displays.orthoProblem().empty();
            health.graph = health.road_graph_off ? nullptr : graph.get();
            const auto next_wake = displays.tick(
                now, poses, frameContext(view_state.get(), style, route, guidance, config.labels, health));
            // A lost GL context made anew (docs/gles-profile.md "Lost contexts"): subscribers hear it.
            if (displays.contextResets() != gpu_resets_told) {
                gpu_resets_told = displays.contextResets();
                ipc::ControlEvent e;
                e.kind = ipc::ControlEventKind::GpuReset;
                e.resets = gpu_resets_told;
                control_server->publish(e);
            }
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
