#include "daemon.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <deque>
#include <map>
#include <set>
#include <sstream>
#include <vector>

#include "attribution_overlay.h"
#include "lifecycle.h"
#include "navmap/ipc/control_server.h"
#include "navmap/ipc/control_state.h"
#include "navmap/ipc/frame_server.h"
#include "navmap/ipc/metrics_registry.h"
#include "navmap/ipc/socket_access.h"
#include "navmap/map/map_scene.h"
#include "navmap/render/map_view.h"
#include "navmap/render/renderer.h"
#include "navmap/render/text/text_engine.h"
#include "navmap/version.h"
#include "vehicle_input.h"

namespace navmap::daemon {

namespace {

using Clock = std::chrono::steady_clock;

// Log lines carry a syslog priority prefix that journald understands (sd-daemon(3)).
struct Log {
    int level = 6;
    void operator()(int priority, const char* fmt, ...) const __attribute__((format(printf, 3, 4))) {
        if (priority > level) return;
        std::fprintf(stderr, "<%d>navmapd: ", priority);
        va_list ap;
        va_start(ap, fmt);
        std::vfprintf(stderr, fmt, ap);
        va_end(ap);
        std::fputc('\n', stderr);
    }
};
constexpr int kErr = 3, kWarning = 4, kNotice = 5, kInfo = 6;

// How long start-up frames wait for the tiles under the camera before they are published anyway
// (a store that lacks the area, a disk that stalls): the display then shows what there is.
constexpr auto kStartupTileWait = std::chrono::seconds(15);

double percentile(std::vector<double> v, double q) {
    if (v.empty()) return 0.0;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(q * (v.size() - 1) + 0.5))];
}

// A bounded window of recent samples for percentiles.
struct Window {
    std::deque<double> values;
    void add(double v) {
        values.push_back(v);
        if (values.size() > 600) values.pop_front();
    }
    [[nodiscard]] double p(double q) const { return percentile({values.begin(), values.end()}, q); }
};

// VmRSS and VmHWM (peak) of this process from /proc/self/status, bytes; 0 when unreadable.
struct Memory {
    std::uint64_t rss = 0, peak = 0;
};
Memory processMemory() {
    Memory m;
    std::FILE* f = std::fopen("/proc/self/status", "r");
    if (!f) return m;
    char line[256];
    while (std::fgets(line, sizeof line, f)) {
        unsigned long long kb = 0;
        if (std::sscanf(line, "VmRSS: %llu kB", &kb) == 1) m.rss = kb * 1024;
        if (std::sscanf(line, "VmHWM: %llu kB", &kb) == 1) m.peak = kb * 1024;
    }
    std::fclose(f);
    return m;
}

std::int64_t realtimeNs(ipc::CanTime t) { return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count(); }

struct ProfileView {
    DisplayProfile profile;
    int target = 0;  // this profile's offscreen target in the one shared renderer
    std::unique_ptr<render::MapView> map_view;
    render::CameraRig rig;
    Clock::time_point next_due{};
    Clock::time_point last_frame{};
    std::uint64_t sequence = 0;
    std::map<std::uint64_t, ipc::CanTime> source_times;  // sequence -> CAN time behind the pose
    Window frame_ms, latency_ms;
    double frame_s_sum = 0.0, latency_s_sum = 0.0;  // since the start (/metrics summaries)
    std::uint64_t latency_count = 0;
    std::unique_ptr<AttributionOverlay> attribution;  // when the profile shows it
    std::size_t tiles_drawn = 0, tiles_pending = 0;  // last frame
    std::uint64_t tiles_uploaded = 0;                 // GPU tile uploads of this profile's frames
    std::uint64_t rendered = 0, published = 0, skipped_idle = 0;
    // Start-up: no frame leaves before one shows the camera's tiles at their level of detail,
    // uploaded (not sky, not a coarse parent). Frames before `first_complete` are dropped.
    std::uint64_t first_complete = ~std::uint64_t{0};
    std::size_t tiles_wanted = 0;  // last frame: tiles the view still waits for
    std::uint64_t held_back = 0;   // frames not published while the map loaded
    // Until its first frame is published, the view's clients get a status instead (about once a
    // second, and at once when a client comes): when the last one went, to how many clients.
    Clock::time_point last_status_sent{};
    std::size_t status_clients = 0;
};

render::ViewMode viewFor(const DisplayProfile& p, const ipc::ViewState* state) {
    if (state) {
        const auto it = state->displays.find(p.name);
        if (it != state->displays.end()) {
            if (it->second.mode == ipc::ViewMode::Bird) return render::ViewMode::Bird;
            if (it->second.mode == ipc::ViewMode::Snail) return render::ViewMode::Snail;
        }
    }
    return p.view;
}

render::Orientation orientationFor(const DisplayProfile& p, const ipc::ViewState* state) {
    if (state) {
        const auto it = state->displays.find(p.name);
        // Only an orientation set over the socket overrides the profile's.
        if (it != state->displays.end() && it->second.orientationSet) {
            return it->second.orientation == ipc::ViewOrientation::NorthUp ? render::Orientation::NorthUp
                                                                           : render::Orientation::HeadingUp;
        }
    }
    return p.orientation;
}

// navmapd's own /metrics families, in base units; the frame server adds its navmap_stream_* ones
// to the same registry (docs/navmapd.md "Observability").
struct MetricsInput {
    const std::vector<ProfileView>* views = nullptr;
    VehicleInputStats input;
    map::TileCacheMetrics cache;
    ipc::ControlServerStats control;
    Memory memory;
    bool position_stale = false;
    std::uint64_t reloads = 0, reload_errors = 0;
};

std::shared_ptr<const ipc::MetricsRegistry> daemonMetrics(const MetricsInput& m) {
    auto reg = std::make_shared<ipc::MetricsRegistry>();
    auto d = [](auto v) { return static_cast<double>(v); };
    reg->gauge("navmap_build_info", "The navmap version this daemon was built from.").sample({{"version", NAVMAP_VERSION}}, 1);
    auto& frame = reg->summary("navmap_frame_seconds",
                               "Frame time per profile (tiles, render, readback submit); quantiles over the last 600 frames.");
    auto& latency = reg->summary("navmap_latency_seconds",
                                 "CAN receive time of the pose to frame published, per profile; quantiles over the last 600 frames.");
    auto& rendered = reg->counter("navmap_frames_rendered_total", "Frames rendered, per profile.");
    auto& published = reg->counter("navmap_frames_published_total", "Frames handed to the frame server, per profile.");
    auto& uploads = reg->counter("navmap_gpu_tile_uploads_total", "Tiles uploaded to the GPU for a profile's frames.");
    for (const auto& v : *m.views) {
        const std::string& n = v.profile.name;
        for (const double q : {0.5, 0.99}) {
            const std::string qs = q == 0.5 ? "0.5" : "0.99";
            frame.sample({{"profile", n}, {"quantile", qs}}, v.frame_ms.p(q) / 1000.0);
            latency.sample({{"profile", n}, {"quantile", qs}}, v.latency_ms.p(q) / 1000.0);
        }
        frame.sample({{"profile", n}}, v.frame_s_sum, "_sum").sample({{"profile", n}}, d(v.rendered), "_count");
        latency.sample({{"profile", n}}, v.latency_s_sum, "_sum").sample({{"profile", n}}, d(v.latency_count), "_count");
        rendered.sample({{"profile", n}}, d(v.rendered));
        published.sample({{"profile", n}}, d(v.published));
        uploads.sample({{"profile", n}}, d(v.tiles_uploaded));
    }
    reg->counter("navmap_can_frames_total", "CAN frames received.").sample(d(m.input.frames));
    reg->counter("navmap_can_rejected_values_total", "Decoded values rejected (out of range, stale counter).")
        .sample(d(m.input.decoder.rejected));
    reg->counter("navmap_can_error_frames_total", "CAN error frames.").sample(d(m.input.can_error_frames));
    reg->counter("navmap_can_kernel_drops_total", "Frames the kernel dropped before the daemon read them.")
        .sample(d(m.input.can_kernel_drops));
    reg->gauge("navmap_position_stale", "1 while the position is lost (no fix within input.stale_after_s).")
        .sample(m.position_stale ? 1 : 0);
    reg->gauge("navmap_tile_cache_bytes", "Decoded tiles resident in the tile cache.").sample(d(m.cache.resident_bytes));
    reg->counter("navmap_tile_cache_hits_total", "Tile requests served from the cache.").sample(d(m.cache.hits));
    reg->counter("navmap_tile_cache_misses_total", "Tile requests queued for loading.").sample(d(m.cache.misses));
    reg->summary("navmap_tile_load_seconds", "Tile load time (read and decode); quantiles over the last 4096 loads.")
        .sample({{"quantile", "0.5"}}, m.cache.load_p50_ms / 1000.0)
        .sample({{"quantile", "0.99"}}, m.cache.load_p99_ms / 1000.0)
        .sample(std::vector<ipc::MetricsRegistry::Label>{}, d(m.cache.loads), "_count");
    reg->counter("navmap_control_errors_total", "Control-socket requests answered with an error.").sample(d(m.control.errors));
    reg->gauge("navmap_process_resident_bytes", "Resident set size (VmRSS).").sample(d(m.memory.rss));
    reg->gauge("navmap_process_peak_resident_bytes", "Peak resident set size (VmHWM).").sample(d(m.memory.peak));
    reg->counter("navmap_config_reloads_total", "Configuration reloads applied (SIGHUP).").sample(d(m.reloads));
    reg->counter("navmap_config_reload_errors_total", "Configuration reloads refused (the running one stays).")
        .sample(d(m.reload_errors));
    return reg;
}

// The MapLibre-convention camera a display follows, if any: one set over the control socket wins;
// a mode set there (bird or snail) means the rig's own view; otherwise the profile's camera.
std::optional<render::MapLibreFollow> cameraFor(const DisplayProfile& p, const ipc::ViewState* state) {
    if (state) {
        const auto it = state->displays.find(p.name);
        if (it != state->displays.end()) {
            if (const auto& c = it->second.camera) return render::MapLibreFollow{c->zoom, c->pitch, c->bearing};
            if (it->second.mode != ipc::ViewMode::Auto) return std::nullopt;
        }
    }
    return p.camera;
}

}  // namespace

int runDaemon(DaemonConfig config, const RunOptions& options) {
    Log log{config.log_level};
    const auto t_start = Clock::now();
    std::unique_ptr<Signals> signals;
    SystemdNotifier systemd;
    try {
        signals = std::make_unique<Signals>();
        ConfigError err;
        if (!validateConfig(config, &err)) throw std::runtime_error("config: " + err.message);

        map::MapScene scene = map::MapScene::open(config.store_path, config.cache_mb << 20);
        const map::Projection projection = scene.projection();  // MapLibre-convention cameras: latitude, true north
        log(kInfo, "store %s: %u tiles, cache %zu MiB", config.store_path.c_str(), scene.store->info().tile_count, config.cache_mb);
        // A damaged road graph degrades like a damaged tile: the map renders, what needs the
        // graph says it is missing (docs/tile-store.md "Damage").
        const std::string road_graph = scene.graph_problem.empty() ? "ok" : "unavailable: " + scene.graph_problem;
        if (!scene.graph_problem.empty()) {
            log(kWarning, "%s; map matching is off (the pose is the raw fix) and the simulator cannot plan a route",
                scene.graph_error.c_str());
        }

        std::set<std::string, std::less<>> display_names;
        for (const auto& p : config.profiles) display_names.insert(p.name);
        auto control_state = std::make_shared<ipc::ControlState>(display_names);
        if (config.night) {
            ipc::SetStyleCommand night;
            night.style = ipc::MapStyle::Night;
            (void)control_state->setStyle(night);
        }

        // Status shared with the control socket's and the HTTP server's threads as snapshots.
        std::atomic<std::shared_ptr<const nlohmann::json>> status_json{std::make_shared<const nlohmann::json>(nlohmann::json::object())};
        std::atomic<std::shared_ptr<const ipc::MetricsRegistry>> daemon_metrics{std::make_shared<const ipc::MetricsRegistry>()};
        control_state->setStatusProvider([&] { return *status_json.load(); });

        // The map matcher is the road graph's only user here: it takes the scene's copy (1.6 MB).
        VehicleInput input(config, projection, scene.store->path(), scene.graph_problem,
                           std::make_shared<const map::RoadGraph>(std::move(scene.graph)), control_state, options.data_dir);

        ipc::ControlServerConfig ccfg;
        ccfg.socketPath = config.control_socket.string();
        ccfg.socketMode = static_cast<mode_t>(config.control_mode);
        for (auto uid : config.control_uids) ccfg.allowedUids.push_back(static_cast<uid_t>(uid));
        for (auto gid : config.control_gids) ccfg.allowedGids.push_back(static_cast<gid_t>(gid));
        if (!config.control_group.empty()) {
            auto gid = ipc::resolveGroup(config.control_group, "control.group");
            if (!gid) throw std::runtime_error(gid.error().message);
            ccfg.socketGroup = gid.value();
        }
        ccfg.idleTimeout = std::chrono::milliseconds(std::llround(config.control_idle_timeout_s * 1000.0));
        auto control = ipc::ControlServer::create(ccfg, *control_state);
        if (!control) throw std::runtime_error(control.error().message);
        std::unique_ptr<ipc::ControlServer> control_server = std::move(control).value();

        ipc::FrameServerOptions fopt;
        fopt.unixPath = config.frame_socket.string();
        if (!config.stream_group.empty()) {
            auto gid = ipc::resolveGroup(config.stream_group, "stream.group");
            if (!gid) throw std::runtime_error(gid.error().message);
            fopt.unixGroup = gid.value();
        }
        for (auto uid : config.stream_uids) fopt.allowedPeers.uids.push_back(static_cast<uid_t>(uid));
        for (auto gid : config.stream_gids) fopt.allowedPeers.gids.push_back(static_cast<gid_t>(gid));
        fopt.maxClientsPerTransport = static_cast<std::size_t>(config.max_clients_per_transport);
        fopt.maxClientsPerUid = static_cast<std::size_t>(config.max_clients_per_uid);
        fopt.ringMemoryBytes = config.ring_memory_mb << 20;
        // Only what the daemon renders is served: its profiles' views and sizes.
        double slowest_fps = 1000.0;
        for (const auto& p : config.profiles) {
            fopt.renderedProfiles.push_back({p.name, p.stream_view, p.width, p.height});
            slowest_fps = std::min(slowest_fps, p.fps);
        }
        // A first frame comes within a frame period of the slowest profile (plus its render), so
        // the timeout is never shorter than two of those periods.
        fopt.handshakeTimeout = std::chrono::milliseconds(
            static_cast<std::int64_t>(std::max(config.handshake_timeout_s, 2.0 / slowest_fps) * 1000));
        fopt.bindAddress = config.http_address;
        fopt.tcpPort = config.tcp_port > 0 ? config.tcp_port : -1;
        fopt.httpPort = config.http_port > 0 ? config.http_port : -1;
        fopt.httpToken = config.http_token;
        fopt.stallTimeout = std::chrono::milliseconds(static_cast<int>(config.client_timeout_s * 1000));
        fopt.mjpegProfile = config.profiles.front().name;  // the page's first stream: a profile rendered here
        // Two slots per ring (double buffering): each costs a frame of shared memory (6.6 MB for
        // the three default profiles), and the seqlock never lets a client keep a frame that was
        // overwritten; a client still copying when the frame after next arrives (one frame period,
        // 33 ms at 30 fps, for a copy of about a millisecond) takes the newest one instead.
        fopt.ringSlots = 2;
        // /metrics: the server's families, then the daemon's latest snapshot (refreshed every second).
        fopt.metrics = [&](ipc::MetricsRegistry& registry) { registry.append(*daemon_metrics.load()); };
        fopt.statusJson = [&] { return status_json.load()->dump(); };
        ipc::FrameServer frames(fopt);
        if (auto st = frames.start(); !st) throw std::runtime_error(st.message());

        // One renderer (one EGL context, one set of shaders and tile GPU resources) for every
        // profile; each profile renders into its own offscreen target with its own readback ring
        // and label layout. Separate contexts cost a copy of every tile per profile and their own
        // llvmpipe JIT code: 270-330 MB peak RSS with three profiles (docs/navmapd.md).
        std::unique_ptr<render::Renderer> renderer;
        std::vector<ProfileView> views;
        // The attribution overlays are laid out with the label text engine (CPU only): one for
        // all profiles that show it, made when the first one needs it.
        std::unique_ptr<render::text::TextEngine> overlay_text;
        const auto makeAttribution = [&](const DisplayProfile& p) -> std::unique_ptr<AttributionOverlay> {
            if (!p.attribution) return nullptr;
            if (!overlay_text) overlay_text = std::make_unique<render::text::TextEngine>();
            return std::make_unique<AttributionOverlay>(*overlay_text, AttributionOverlay::kOsmAttribution, p.width, p.height);
        };
        for (const auto& p : config.profiles) {
            ProfileView v;
            v.profile = p;
            if (!renderer) {
                render::RendererOptions ro;
                ro.platform = render::parsePlatform(config.egl_platform).value_or(render::Platform::Auto);
                ro.width = p.width;
                ro.height = p.height;
                ro.msaa_samples = config.msaa;
                ro.max_tile_uploads_per_frame = 8;  // a burst of new tiles spreads over frames
                // GPU tiles kept: each costs about 0.45 MB (land-cover texture, terrain and road
                // buffers), and without a cap they pile up along a drive. A tile that any profile
                // drew in its latest frame is never evicted (the renderer counts per target, not
                // per render call), so the cap only bounds the spare tiles kept for level-of-detail
                // changes and turns. The three default views draw 15-25 tiles each (57 together on
                // the Andorra drive, fewer distinct ones); 16 + 8 per profile, at least 32 (40 for
                // three) re-uploads 106 tiles in 20 s of the replayed drive against 102 with 48,
                // for 4.5 MB less (docs/navmapd.md).
                ro.tile_resource_cache = config.gpu_tile_cache > 0
                                             ? config.gpu_tile_cache
                                             : std::max(32, 16 + 8 * static_cast<int>(config.profiles.size()));
                // Finished readbacks leave at once (collected after each render and polled while
                // in flight). 0 = the renderer's choice: on llvmpipe a frame is read straight into
                // its image (glReadPixels waits for the rasterization there even into a pixel-pack
                // buffer, so buffers would only cost width x height x 4 bytes each: 6.9 MB for the
                // three default profiles); on a GPU two pixel-pack buffers per target.
                ro.readback_ring = 0;
                renderer = options.noop_renderer ? render::Renderer::createNoop(ro) : render::Renderer::create(ro);
                v.target = renderer->currentTarget();
            } else {
                v.target = renderer->addTarget(p.width, p.height);
            }
            v.map_view = std::make_unique<render::MapView>(scene.cache);
            v.attribution = makeAttribution(p);
            v.rig.setMode(p.view);
            v.rig.setOrientation(p.orientation);
            const auto& dev = renderer->device();
            log(kInfo, "profile %s %dx%d @ %.0f fps (%s): target %d, %s on %s, %s, MSAA %dx", p.name.c_str(), p.width,
                p.height, p.fps, p.stream_view.c_str(), v.target, dev.backend.c_str(), dev.platform.c_str(),
                dev.renderer.c_str(), dev.msaa_samples);
            views.push_back(std::move(v));
        }

        input.start();
        if (auto st = control_server->start(); !st) throw std::runtime_error(st.message());
        std::string endpoints = "control " + config.control_socket.string() + ", frames " + config.frame_socket.string();
        if (frames.httpPort() > 0) endpoints += ", http://" + config.http_address + ":" + std::to_string(frames.httpPort()) + "/";
        if (frames.tcpPort() > 0) endpoints += ", tcp " + std::to_string(frames.tcpPort());
        log(kNotice, "ready in %.0f ms: %s; input %s; navmap %s",
            std::chrono::duration<double, std::milli>(Clock::now() - t_start).count(), endpoints.c_str(),
            input.stats().source.c_str(), NAVMAP_VERSION);
        systemd.ready("rendering " + std::to_string(views.size()) + " profiles; " + endpoints);

        // Route geometry for the renderer, rebuilt when the control snapshot's version changes.
        render::RouteGeometry route_geometry;
        std::uint64_t route_version = ~std::uint64_t{0};
        bool was_stale = false;
        std::set<std::uint64_t> warned_flat;  // tiles reported as lacking elevation data
        std::string route_id;
        double route_driven_max = 0.0;
        Clock::time_point last_progress_event{}, last_status{};
        Clock::time_point last_frame_done = Clock::now();
        std::uint64_t reloads = 0, reload_errors = 0;  // SIGHUP: applied / refused
        std::string last_reload_error;
        const auto terrain = [&](double x, double y) { return views.front().map_view->terrainHeight(x, y); };

        // Publishes finished readbacks of `v`, oldest first, with the CAN time behind each pose.
        const auto publishFinished = [&](ProfileView& v, std::vector<render::Frame>& finished) {
            for (auto& done : finished) {
                if (done.sequence < v.first_complete) {
                    ++v.held_back;  // rendered before the map under the camera was drawable
                    v.source_times.erase(v.source_times.begin(), v.source_times.upper_bound(done.sequence));
                    continue;
                }
                if (v.attribution && done.image.width == v.profile.width && done.image.height == v.profile.height) {
                    v.attribution->apply(done.image.rgba.data(), done.image.width * 4);
                }
                ipc::FrameView fv;
                fv.pixels = done.image.rgba.data();
                fv.width = done.image.width;
                fv.height = done.image.height;
                fv.format = ipc::PixelFormat::Rgba8;
                const auto it = v.source_times.find(done.sequence);
                const ipc::CanTime source = it != v.source_times.end() ? it->second : ipc::CanTime{};
                fv.sourceTimeNs = realtimeNs(source);
                frames.publish(v.profile.name, fv);  // routed by profile: same view and size, other style
                ++v.published;
                if (source != ipc::CanTime{}) {
                    const double latency_ms = std::chrono::duration<double, std::milli>(ipc::CanClock::now() - source).count();
                    v.latency_ms.add(latency_ms);
                    v.latency_s_sum += latency_ms / 1000.0;
                    ++v.latency_count;
                }
                v.source_times.erase(v.source_times.begin(), v.source_times.upper_bound(done.sequence));
            }
        };

        bool stop = false;
        while (!stop) {
            const auto now = Clock::now();
            if (options.run_for_s && std::chrono::duration<double>(now - t_start).count() >= *options.run_for_s) break;

            const auto state = input.state();
            const ipc::CanTime can_now = ipc::CanClock::now();
            const EstimatedPose pose = state->poseAt(can_now);
            const auto view_state = control_state->view();
            const auto route = control_state->route();
            if (route && route->version != route_version) {
                route_version = route->version;
                const std::uint64_t geometry_version = route_geometry.version + 1;  // the renderers re-drape it
                route_geometry = {};
                route_geometry.version = geometry_version;
                const map::Projection proj = scene.projection();
                double measure = 0.0;
                for (std::size_t i = 0; i < route->points.size(); ++i) {
                    const auto p = proj.forward(route->points[i].lat, route->points[i].lon);
                    if (i > 0) measure += std::hypot(p.x - route_geometry.points.back().x, p.y - route_geometry.points.back().y);
                    route_geometry.points.emplace_back(p.x, p.y, 0.0);
                    route_geometry.measure_m.push_back(measure);
                }
                route_id = route->id;
                route_driven_max = 0.0;
                log(kInfo, "route %s: %zu points, %.1f km", route_id.c_str(), route_geometry.points.size(), measure / 1000.0);
            }
            // No per-tick heights: each renderer drapes the route onto the tiles it draws.
            if (pose.onRoute) route_driven_max = std::max(route_driven_max, pose.routeDrivenM);

            // Position lost / regained and route progress go to subscribers.
            if (pose.valid && pose.stale != was_stale) {
                ipc::ControlEvent e;
                e.kind = pose.stale ? ipc::ControlEventKind::PositionLost : ipc::ControlEventKind::PositionRegained;
                e.sinceS = pose.sinceFixS;
                control_server->publish(e);
                if (pose.stale) log(kWarning, "position lost (%.1f s without a fix)", pose.sinceFixS);
                else log(kInfo, "position regained");
                was_stale = pose.stale;
            }
            if (!route_id.empty() && pose.onRoute && now - last_progress_event > std::chrono::seconds(1)) {
                ipc::ControlEvent e;
                e.kind = ipc::ControlEventKind::RouteProgress;
                e.routeId = route_id;
                e.drivenM = route_driven_max;
                e.remainingM = std::max(0.0, (route_geometry.measure_m.empty() ? 0.0 : route_geometry.measure_m.back()) - route_driven_max);
                control_server->publish(e);
                last_progress_event = now;
            }

            const auto active = frames.activeProfiles();
            render::MapStyle style = view_state && view_state->style == ipc::MapStyle::Night ? render::MapStyle::night()
                                                                                               : render::MapStyle::day();
            Clock::time_point next_wake = now + std::chrono::milliseconds(50);
            // Start-up: frames of a view wait for the tiles under its camera (first_complete), and
            // the frame server drops a client without a first frame after handshake_timeout_s. Its
            // clients get a status meanwhile: "loading", how many tiles are still wanted, how many
            // frames were held back. Each one restarts that timeout; the first frame ends them.
            for (auto& v : views) {
                if (v.published > 0) continue;
                std::size_t clients = 0;
                for (const auto& a : active) {
                    if (a.view == v.profile.stream_view && a.width == v.profile.width && a.height == v.profile.height) {
                        clients += a.clients;
                    }
                }
                const bool new_client = clients > v.status_clients;
                v.status_clients = clients;
                if (clients == 0 || (!new_client && now - v.last_status_sent < std::chrono::seconds(1))) continue;
                v.last_status_sent = now;
                const nlohmann::ordered_json status = {  // in the documented order, for people reading it
                    {"state", "loading"},
                    {"profile", v.profile.name},
                    {"view", v.profile.stream_view},
                    {"tiles_wanted", v.tiles_wanted},
                    {"held_back", v.held_back},
                    {"waited_ms", std::chrono::duration_cast<std::chrono::milliseconds>(now - t_start).count()},
                    {"max_wait_ms", std::chrono::duration_cast<std::chrono::milliseconds>(kStartupTileWait).count()}};
                if (auto st = frames.publishStatus(v.profile.name, v.profile.width, v.profile.height,
                                                   status.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
                    !st) {
                    log(kWarning, "profile %s: %s", v.profile.name.c_str(), st.message().c_str());
                }
            }
            for (auto& v : views) {
                if (now < v.next_due) {
                    next_wake = std::min(next_wake, v.next_due);
                    continue;
                }
                v.next_due = std::max(v.next_due + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(1.0 / v.profile.fps)), now);
                next_wake = std::min(next_wake, v.next_due);
                const bool wanted = options.render_all_profiles ||
                                    std::any_of(active.begin(), active.end(), [&](const ipc::ActiveProfile& a) {
                                        return a.profile == v.profile.name;
                                    });
                if (!wanted) {
                    ++v.skipped_idle;  // nobody watches this profile: render nothing
                    continue;
                }
                const auto t0 = Clock::now();
                const double dt = v.last_frame == Clock::time_point{} ? 0.0 : std::chrono::duration<double>(t0 - v.last_frame).count();
                v.last_frame = t0;
                v.rig.setMode(viewFor(v.profile, view_state.get()));
                v.rig.setOrientation(orientationFor(v.profile, view_state.get()));
                if (const auto camera = cameraFor(v.profile, view_state.get()); camera != v.rig.mapLibreFollow()) {
                    if (camera) v.rig.setMapLibreFollow(*camera, projection, v.profile.height);
                    else v.rig.clearMapLibreFollow();
                }
                // The freshest pose for this profile: profiles render one after another, and a
                // pose taken at the start of the tick would age by the renders before this one.
                const EstimatedPose fresh = input.state()->poseAt(ipc::CanClock::now());
                render::VehiclePose vp;
                if (fresh.valid) {
                    vp.position = {fresh.x, fresh.y, terrain(fresh.x, fresh.y)};
                    vp.heading_deg = fresh.headingDeg;
                    vp.speed_mps = fresh.speedMps;
                } else {
                    // No fix yet: look at the middle of the map.
                    const auto& s = scene.store->info();
                    const auto c = scene.toPlanar((s.south + s.north) / 2, (s.west + s.east) / 2);
                    vp.position = {c.x, c.y, terrain(c.x, c.y)};
                }
                render::MapFrame frame;
                frame.camera = v.rig.update(vp, std::min(dt, 0.5), terrain);
                v.map_view->select(frame, double(v.profile.width) / v.profile.height, v.profile.height);  // tiles + geomorph
                frame.route = route_geometry.points.size() >= 2 ? &route_geometry : nullptr;
                frame.route_progress_m = route_driven_max;
                frame.layers = layersFor(v.profile, config.labels);
                frame.frame_dt_s = std::min(dt, 0.5);
                if (fresh.valid) frame.marker = render::MarkerState{vp.position, vp.heading_deg, fresh.stale};
                renderer->useTarget(v.target);
                renderer->setMapStyle(style);
                renderer->renderMap(frame);
                v.tiles_drawn = renderer->mapStats().tiles_drawn;
                v.tiles_pending = renderer->mapStats().tiles_pending;
                v.tiles_wanted = v.map_view->lastSelection().wanted.size();
                v.tiles_uploaded += renderer->mapStats().tiles_uploaded;
                for (const auto& flat : renderer->mapStats().new_flat_tiles) {
                    if (warned_flat.insert(flat.id.key()).second) {
                        log(kWarning, "tile %s: %.0f%% of its area has no elevation data and renders flat",
                            flat.id.toString().c_str(), 100.0 * (1.0 - flat.coverage));
                    }
                }
                const std::uint64_t seq = v.sequence++;
                v.source_times[seq] = fresh.sourceTime;
                if (v.first_complete == ~std::uint64_t{0}) {
                    const bool complete = v.tiles_drawn > 0 && v.tiles_pending == 0 && v.tiles_wanted == 0;
                    const bool overdue = now - t_start > kStartupTileWait;
                    if (complete || overdue) {
                        v.first_complete = seq;
                        if (overdue && !complete) {
                            log(kWarning, "profile %s: map tiles still loading after %.0f s (%zu wanted, %zu waiting for upload); publishing anyway",
                                v.profile.name.c_str(), std::chrono::duration<double>(kStartupTileWait).count(), v.tiles_wanted,
                                v.tiles_pending);
                        } else {
                            log(kInfo, "profile %s: map ready after %.0f ms (%llu frames held back)", v.profile.name.c_str(),
                                std::chrono::duration<double, std::milli>(Clock::now() - t_start).count(),
                                static_cast<unsigned long long>(seq));
                        }
                    }
                }
                // The ring hands back a frame only when full; collect what has finished now so
                // frames leave in the tick that rendered them.
                std::vector<render::Frame> finished;
                if (auto oldest = renderer->readAsync(seq)) finished.push_back(std::move(*oldest));
                for (auto& f : renderer->collectReadbacks()) finished.push_back(std::move(f));
                publishFinished(v, finished);
                ++v.rendered;
                const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
                v.frame_ms.add(frame_ms);
                v.frame_s_sum += frame_ms / 1000.0;
                last_frame_done = Clock::now();
            }

            // Readbacks still in flight: the rasterizer finishes them on its own threads while the
            // loop renders the next profiles or sleeps. Send each as soon as it is done (polled
            // every few milliseconds, never waited for) instead of at that profile's next tick,
            // which would add a frame interval to its CAN -> frame latency.
            for (auto& v : views) {
                if (v.source_times.empty()) continue;  // nothing in flight for this profile
                renderer->useTarget(v.target);
                auto done = renderer->collectReadbacks();
                publishFinished(v, done);
                if (!v.source_times.empty()) next_wake = std::min(next_wake, Clock::now() + std::chrono::milliseconds(3));
            }

            // Health: WATCHDOG=1 only while frames keep completing (or nobody needs any).
            const bool rendering_wanted = options.render_all_profiles || !active.empty();
            if (!rendering_wanted || std::chrono::duration<double>(Clock::now() - last_frame_done).count() < config.watchdog_max_frame_s) {
                systemd.watchdog();
            }

            if (now - last_status > std::chrono::seconds(1)) {
                last_status = now;
                const auto in = input.stats();
                const auto fs = frames.stats();
                const auto cache = scene.cache->metrics();
                const auto cs = control_server->stats();
                nlohmann::json st;
                st["version"] = NAVMAP_VERSION;
                st["uptime_s"] = std::chrono::duration<double>(now - t_start).count();
                const Memory mem = processMemory();
                st["memory"] = {{"rss_bytes", mem.rss}, {"peak_rss_bytes", mem.peak}};
                st["config"] = {{"path", options.config_path ? options.config_path->string() : std::string()},
                                {"reloads", reloads}, {"reload_errors", reload_errors},
                                {"last_reload_error", last_reload_error}, {"style", config.night ? "night" : "day"}};
                st["input"] = {{"source", in.source}, {"frames", in.frames}, {"decoded_values", in.decoder.values},
                               {"rejected_values", in.decoder.rejected}, {"counter_gaps", in.decoder.counterGaps},
                               {"rejected_fixes", in.estimator.rejectedJump + in.estimator.rejectedRange + in.estimator.rejectedNaN},
                               {"can_error_frames", in.can_error_frames}, {"can_bus_off", in.can_bus_off},
                               {"can_kernel_drops", in.can_kernel_drops}, {"can_state", in.can_state},
                               {"replay_malformed_lines", in.replay_malformed_lines},
                               {"replay_time_errors", in.replay_time_errors}, {"error", in.error}};
                st["road_graph"] = road_graph;
                st["position"] = {{"valid", pose.valid}, {"stale", pose.stale}, {"speed_kmh", pose.speedMps * 3.6},
                                  {"heading_deg", pose.headingDeg}, {"match_confidence", pose.matchConfidence}};
                if (!route_id.empty()) st["route"] = {{"id", route_id}, {"driven_m", route_driven_max}};
                nlohmann::json profiles = nlohmann::json::array();
                for (const auto& v : views) {
                    profiles.push_back({{"name", v.profile.name}, {"rendered", v.rendered}, {"published", v.published},
                                        {"frame_p50_ms", v.frame_ms.p(0.5)}, {"frame_p99_ms", v.frame_ms.p(0.99)},
                                        {"latency_p50_ms", v.latency_ms.p(0.5)}, {"latency_p99_ms", v.latency_ms.p(0.99)},
                                        {"tiles_drawn", v.tiles_drawn}, {"tiles_pending", v.tiles_pending},
                                        {"state", v.first_complete == ~std::uint64_t{0} ? "loading map" : "rendering"},
                                        {"held_back", v.held_back}, {"tiles_wanted", v.tiles_wanted},
                                        {"tiles_uploaded", v.tiles_uploaded}, {"attribution", v.attribution != nullptr}});
                }
                st["profiles"] = profiles;
                st["stream"] = {{"clients", fs.clients}, {"frames_sent", fs.framesSent}, {"frames_dropped", fs.framesDropped},
                                {"stall_disconnects", fs.stallDisconnects}, {"handshake_errors", fs.handshakeErrors},
                                {"timeouts", {{"handshake", fs.handshakeTimeouts}, {"first_frame", fs.firstFrameTimeouts}}},
                                {"refusals", {{"peer", fs.refusedPeer}, {"transport_full", fs.refusedTransportFull},
                                              {"uid_full", fs.refusedUidFull}, {"not_rendered", fs.refusedNotRendered},
                                              {"ring_memory", fs.refusedRingMemory}, {"http_host", fs.refusedHost},
                                              {"http_token", fs.refusedToken}}},
                                {"ring_bytes", fs.ringBytes}, {"last_error", fs.lastError}};
                st["tile_cache"] = {{"resident_bytes", cache.resident_bytes}, {"hits", cache.hits}, {"misses", cache.misses},
                                    {"load_p99_ms", cache.load_p99_ms}, {"corrupt", cache.corrupt}};
                status_json.store(std::make_shared<const nlohmann::json>(std::move(st)));
                MetricsInput mi;
                mi.views = &views;
                mi.input = in;
                mi.cache = cache;
                mi.control = cs;
                mi.memory = mem;
                mi.position_stale = pose.stale;
                mi.reloads = reloads;
                mi.reload_errors = reload_errors;
                daemon_metrics.store(daemonMetrics(mi));
                std::ostringstream line;
                line << fs.clients << " clients, " << (pose.valid ? (pose.stale ? "position lost" : "position ok") : "no position yet");
                for (const auto& v : views) line << ", " << v.profile.name << " " << v.rendered << " frames";
                systemd.status(line.str());
            }

            const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(next_wake - Clock::now());
            switch (signals->wait(std::max(wait, std::chrono::milliseconds(0)))) {
                case SignalEvent::Stop:
                    stop = true;
                    break;
                case SignalEvent::Reload: {
                    systemd.reloading();
                    if (options.config_path) {
                        ConfigError rerr;
                        auto fresh = loadConfig(*options.config_path, &rerr);
                        if (fresh) {
                            // What a reload does not change (store, input, sockets, ...) keeps its
                            // running value, command-line overrides and built-in defaults included,
                            // so the file is validated as it will run.
                            DaemonConfig merged = config;
                            merged.night = fresh->night;
                            merged.profiles = fresh->profiles;
                            fresh = std::move(merged);
                        }
                        if (!fresh || !validateConfig(*fresh, &rerr)) {
                            log(kErr, "reload: %s (keeping the running configuration)", rerr.message.c_str());
                            ++reload_errors;
                            last_reload_error = rerr.message;
                        } else {
                            // Style and per-profile view settings change in place; clients stay connected.
                            ipc::SetStyleCommand s;
                            s.style = fresh->night ? ipc::MapStyle::Night : ipc::MapStyle::Day;
                            (void)control_state->setStyle(s);
                            config.night = fresh->night;
                            for (auto& v : views) {
                                const auto p = findProfile(fresh->profiles, v.profile.name);
                                if (p && p->width == v.profile.width && p->height == v.profile.height) {
                                    v.profile.fps = p->fps;
                                    v.profile.view = p->view;
                                    v.profile.orientation = p->orientation;
                                    v.profile.roads = p->roads;
                                    v.profile.glow_roads = p->glow_roads;
                                    v.profile.label_aura = p->label_aura;
                                    v.profile.road_selection = p->road_selection;
                                    if (p->attribution != v.profile.attribution) {
                                        v.profile.attribution = p->attribution;
                                        v.attribution = makeAttribution(v.profile);
                                    }
                                    v.profile.camera = p->camera;
                                    v.next_due = Clock::now();  // the new rate applies from the next tick
                                } else if (p) {
                                    log(kWarning, "reload: profile %s: a new size (%dx%d) needs a restart; keeping %dx%d",
                                        v.profile.name.c_str(), p->width, p->height, v.profile.width, v.profile.height);
                                }
                            }
                            ++reloads;
                            log(kNotice, "reloaded %s: style %s", options.config_path->c_str(), fresh->night ? "night" : "day");
                        }
                    }
                    systemd.ready("reloaded");
                    last_status = {};  // status and metrics show the reload at once
                    break;
                }
                case SignalEvent::None:
                    break;
            }
        }

        log(kNotice, "stopping");
        systemd.stopping();
        control_server->stop();
        input.stop();
        frames.stop();  // closes every client connection: they see the stream end
        const Memory mem = processMemory();
        log(kNotice, "peak RSS %.1f MiB (%zu profiles, one renderer with %zu targets)", static_cast<double>(mem.peak) / (1 << 20),
            views.size(), renderer ? renderer->targetCount() : std::size_t{0});
        for (auto& v : views) {
            log(kInfo, "profile %s: %llu frames rendered, %llu published, frame p50 %.1f ms p99 %.1f ms, latency p50 %.1f ms p99 %.1f ms, %llu tile uploads",
                v.profile.name.c_str(), static_cast<unsigned long long>(v.rendered), static_cast<unsigned long long>(v.published),
                v.frame_ms.p(0.5), v.frame_ms.p(0.99), v.latency_ms.p(0.5), v.latency_ms.p(0.99),
                static_cast<unsigned long long>(v.tiles_uploaded));
        }
        return 0;
    } catch (const std::exception& e) {
        log(kErr, "%s", e.what());
        return 1;
    }
}

}  // namespace navmap::daemon
