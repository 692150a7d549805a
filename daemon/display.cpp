// SPDX-License-Identifier: Apache-2.0
#include "display.h"

#include <algorithm>

#include <nlohmann/json.hpp>

#include "navmap/render/maneuver_arrow.h"

namespace navmap::daemon {

namespace {

// How long start-up frames wait for the tiles under the camera before they are published anyway
// (a store that lacks the area, a disk that stalls): the display then shows what there is.
constexpr auto kStartupTileWait = std::chrono::seconds(15);

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
        if (it != state->displays.end() && it->second.orientation_set) {
            return it->second.orientation == ipc::ViewOrientation::NorthUp ? render::Orientation::NorthUp
                                                                           : render::Orientation::HeadingUp;
        }
    }
    return p.orientation;
}

// The MapLibre-convention camera a display follows, if any: one set over the control socket wins;
// a mode set there (bird or snail) means the rig's own view; otherwise the profile's camera.
std::optional<render::MapLibreFollow> cameraFor(const DisplayProfile& p, const ipc::ViewState* state) {
    if (state) {
        const auto it = state->displays.find(p.name);
        if (it != state->displays.end()) {
            if (const auto& c = it->second.camera) return render::MapLibreFollow{c->zoom, c->pitch_deg, c->bearing_deg};
            if (it->second.mode != ipc::ViewMode::Auto) return std::nullopt;
        }
    }
    return p.camera;
}

}  // namespace

Display::Display(DisplayProfile profile, render::TargetHandle target, std::shared_ptr<map::TileCache> cache,
                 std::unique_ptr<AttributionOverlay> attribution, Clock::time_point started, Clock::time_point exec,
                 Log log)
    : m_profile(std::move(profile)),
      m_target(target),
      m_started(started),
      m_exec(exec),
      m_log(log),
      m_map_view(std::move(cache)),
      m_attribution(std::move(attribution)) {
    m_rig.setMode(m_profile.view);
    m_rig.setOrientation(m_profile.orientation);
}

void Display::reconfigure(const DisplayProfile& p, std::unique_ptr<AttributionOverlay> attribution) {
    m_profile.fps = p.fps;
    m_profile.view = p.view;
    m_profile.orientation = p.orientation;
    m_profile.roads = p.roads;
    m_profile.glow_roads = p.glow_roads;
    m_profile.label_aura = p.label_aura;
    m_profile.road_selection = p.road_selection;
    m_profile.speed_limit_sign = p.speed_limit_sign;
    m_profile.street_bar = p.street_bar;
    m_profile.lane_guidance = p.lane_guidance;
    if (p.attribution != m_profile.attribution) {
        m_profile.attribution = p.attribution;
        m_attribution = std::move(attribution);
        m_attribution_pixels = {};  // made again for the exported frames
    }
    m_profile.camera = p.camera;
}

void Display::addGuidance(render::MapFrame& frame, const GuidanceSnapshot& guidance, const render::RouteGeometry* route,
                          bool hud) {
    if (!guidance.active) return;
    if (route) {
        // The arrow's shaft runs along the incoming road, through the junction (round a
        // roundabout to its exit) and on to the head on the outgoing road (docs/guidance.md).
        for (const GuidanceArrow& a : guidance.arrows) {
            render::ManeuverArrow arrow =
                render::cutManeuverArrow(*route, a.junction_m, kArrowBeforeM, a.end_m - a.junction_m + kArrowAfterM);
            arrow.emphasis = a.emphasis;
            if (arrow.points.size() >= 2) frame.arrows.push_back(std::move(arrow));
        }
    }
    // The lanes before the next manoeuvre: in the HUD's panel, on their own panel elsewhere.
    std::optional<render::LaneRow> lanes;
    if (m_profile.lane_guidance && guidance.lanes && !guidance.off_route)
        lanes = render::LaneRow{guidance.lanes->lanes, guidance.lanes->recommended};
    if (!hud) {
        frame.lanes = std::move(lanes);
        return;
    }
    render::GuidanceOverlay overlay;
    if (guidance.off_route) {
        overlay.symbol = render::ManeuverSymbol::UTurn;
        overlay.distance = "off route";
    } else if (guidance.next) {
        overlay.symbol = guidance.next->type;
        overlay.roundabout_exit = guidance.next->exit;
        overlay.distance = guidance.distance_text;
        overlay.street = guidance.street;
        overlay.lanes = std::move(lanes);
        // The HUD's corridor: the roads that branch at the next junction, nothing else.
        frame.guidance_roads = junctionRoads(frame, glm::dvec2(guidance.next_junction.x, guidance.next_junction.y));
    } else if (guidance.arrived) {
        overlay.symbol = render::ManeuverSymbol::Arrive;
        overlay.distance = "now";
    }
    overlay.remaining_distance = guidance.remaining_distance;
    overlay.remaining_time = guidance.remaining_time;
    frame.guidance = std::move(overlay);
}

const std::vector<std::vector<glm::dvec3>>& Display::junctionRoads(const render::MapFrame& frame, glm::dvec2 junction) {
    // The roads at the junction change only with the junction or the drawn tiles: cut them from
    // the tiles once, not every frame.
    std::vector<const map::Tile*> tiles;
    tiles.reserve(frame.tiles.size());
    for (const auto& t : frame.tiles) tiles.push_back(t.get());
    if (junction != m_roads_junction || tiles != m_roads_tiles) {
        m_roads = render::junctionRoads(frame.tiles, junction, kJunctionRoadsM);
        m_roads_junction = junction;
        m_roads_tiles = std::move(tiles);
    }
    return m_roads;
}

void Display::rebase() {
    m_roads.clear();
    m_roads_tiles.clear();
    m_roads_junction = glm::dvec2(std::numeric_limits<double>::quiet_NaN());
}

bool Display::draw(render::Renderer& renderer, const PoseSource& poses, const FrameContext& context,
                   const map::Projection& projection) {
    m_frame_start = Clock::now();
    const double dt =
        m_last_frame == Clock::time_point{} ? 0.0 : std::chrono::duration<double>(m_frame_start - m_last_frame).count();
    m_last_frame = m_frame_start;
    m_rig.setMode(viewFor(m_profile, context.view_state));
    m_rig.setOrientation(orientationFor(m_profile, context.view_state));
    if (const auto camera = cameraFor(m_profile, context.view_state); camera != m_rig.mapLibreFollow()) {
        if (camera)
            m_rig.setMapLibreFollow(*camera, projection, m_profile.height);
        else
            m_rig.clearMapLibreFollow();
    }
    // The freshest pose for this display: displays render one after another, and a pose taken
    // at the start of the tick would age by the renders before this one.
    const FramePose pose = poses.at(ipc::CanClock::now());
    m_frame_source = pose.source_time;
    m_last_pose = pose.vehicle;
    const GroundHeight& ground = poses.ground();
    render::MapFrame frame;
    frame.camera =
        m_rig.update(pose.vehicle, std::min(dt, 0.5), [&ground](double x, double y) { return ground(x, y); });
    m_map_view.select(frame, double(m_profile.width) / m_profile.height, m_profile.height);  // tiles + geomorph
    if (!mapReady()) {
        // Start-up: a frame that still lacks tiles under the camera would be held back. Rendering
        // it costs a whole frame of rasterization (on llvmpipe the CPU the tile loader and the
        // other profiles need); the request above is all it is good for. Once every tile is
        // resident, that frame uploads them all at once and is published.
        m_stats.tiles_wanted = m_map_view.lastSelection().wanted.size();
        m_log(Log::kDebug, "start-up: profile %s tick at %.0f ms: %zu tiles wanted%s", m_profile.name.c_str(),
              std::chrono::duration<double, std::milli>(m_frame_start - m_exec).count(), m_stats.tiles_wanted,
              m_hold_first ? ", waiting for the profiles listed before it" : "");
        const bool waiting = m_frame_start - m_started <= kStartupTileWait;
        if ((m_stats.tiles_wanted > 0 || m_hold_first) && waiting) {
            ++m_stats.held_back;
            return false;
        }
        frame.upload_all = true;
    }
    m_frame_annotation = m_annotator.annotate(pose.estimate, context.health, context.guidance, projection, frame,
                                              m_map_view.lastSelection(), m_map_view.cache());
    frame.route = context.route;
    frame.route_progress_m = context.route_progress_m;
    frame.layers = layersFor(m_profile, context.labels);
    // In a tunnel the labels of the surface above are left out (docs/navmapd.md "Tunnels").
    frame.hide_surface_labels = pose.estimate.valid && pose.estimate.in_tunnel;
    frame.frame_dt_s = std::min(dt, 0.5);
    frame.marker = pose.marker;
    const bool hud = isGuidanceView(m_profile);
    if (context.guidance) addGuidance(frame, *context.guidance, context.route, hud);
    // The limit of the road driven, where it is known and the match certain (docs/rendering.md).
    if (m_profile.speed_limit_sign && pose.speed_limit_kmh > 0)
        frame.speed_limit = render::SpeedLimitSign{pose.speed_limit_kmh, *m_profile.speed_limit_sign};
    // The road driven, once the certain match has held its street for 2 s of pose time
    // (StreetBarHold). The hold runs every frame, so that a bar switched on by a reload shows
    // the street at once.
    std::optional<render::StreetBar> matched;
    if (pose.estimate.valid && pose.estimate.road_match_certain) matched = m_annotator.street();
    const double pose_s = std::chrono::duration<double>(pose.estimate.time.time_since_epoch()).count();
    if (const auto& street = m_street_hold.update(pose_s, matched); street && m_profile.street_bar)
        frame.street_bar = *street;
    renderer.setMapStyle(hud ? render::MapStyle::hud() : context.style);
    // At debug level the start-up frames are timed per pass too (their log line says where the
    // first frame's time goes); not otherwise: the timing waits for the GPU after every pass.
    const bool startup_passes = m_stats.rendered < 3 && m_log.enabled(Log::kDebug);
    frame.profile_passes = m_stats.rendered % kPassSampleEvery == kPassSampleEvery - 1 || startup_passes;
    const auto t_render = Clock::now();
    m_stats.pass_ms["select"].add(std::chrono::duration<double, std::milli>(t_render - m_frame_start).count());
    renderer.renderMap(m_target, frame);
    m_stats.pass_ms["render"].add(std::chrono::duration<double, std::milli>(Clock::now() - t_render).count());
    if (frame.profile_passes) samplePasses(renderer.mapStats());
    if (m_stats.rendered < 3) {
        const auto now = Clock::now();
        const render::MapFrameStats& s = renderer.mapStats();
        m_log(Log::kInfo, "start-up: profile %s frame %llu at %.0f ms (%.0f ms): %zu tiles drawn, %zu pending",
              m_profile.name.c_str(), static_cast<unsigned long long>(m_stats.rendered),
              std::chrono::duration<double, std::milli>(now - m_exec).count(),
              std::chrono::duration<double, std::milli>(now - m_frame_start).count(), s.tiles_drawn, s.tiles_pending);
        if (startup_passes)
            m_log(Log::kDebug,
                  "start-up: profile %s frame %llu passes: uploads %.0f, terrain %.0f, buildings %.0f, roads %.0f, "
                  "route %.0f, labels %.0f, aura %.0f, glow %.0f ms",
                  m_profile.name.c_str(), static_cast<unsigned long long>(m_stats.rendered), s.uploads_ms, s.terrain_ms,
                  s.buildings_ms, s.roads_ms + s.sv_roads_ms + s.outlines_ms, s.route_ms, s.label_block_ms, s.aura_ms,
                  s.glow_ms);
    }
    m_stats.tiles_drawn = renderer.mapStats().tiles_drawn;
    m_stats.tiles_pending = renderer.mapStats().tiles_pending;
    m_stats.tiles_wanted = m_map_view.lastSelection().wanted.size();
    m_stats.tiles_uploaded += renderer.mapStats().tiles_uploaded;
    return true;
}

void Display::finishFrame(render::Renderer& renderer, ipc::FrameServer& frames, Clock::time_point tick,
                          const ipc::ActiveProfile* active) {
    const std::uint64_t seq = m_sequence++;
    m_source_times[seq] = {m_frame_source, std::move(m_frame_annotation)};
    if (m_first_complete == kNone) {
        const bool complete = m_stats.tiles_drawn > 0 && m_stats.tiles_pending == 0 && m_stats.tiles_wanted == 0;
        const bool overdue = tick - m_started > kStartupTileWait;
        if (complete || overdue) {
            m_first_complete = seq;
            if (overdue && !complete) {
                m_log(Log::kWarning,
                      "profile %s: map tiles still loading after %.0f s (%zu wanted, %zu waiting for upload); "
                      "publishing anyway",
                      m_profile.name.c_str(), std::chrono::duration<double>(kStartupTileWait).count(),
                      m_stats.tiles_wanted, m_stats.tiles_pending);
            } else {
                m_log(Log::kInfo, "profile %s: map ready after %.0f ms (%llu frames held back)", m_profile.name.c_str(),
                      std::chrono::duration<double, std::milli>(Clock::now() - m_started).count(),
                      static_cast<unsigned long long>(seq));
            }
        }
    }
    // Clients of payload dmabuf get the frame in an exported buffer; only the others need it read
    // back (render_all without clients reads back too: tests look at those frames).
    const std::size_t dmabuf_clients = active ? active->dmabuf_clients : 0;
    const bool read_back = !active || active->clients > dmabuf_clients;
    const auto t_publish = Clock::now();
    if (dmabuf_clients > 0) exportDmabuf(renderer, frames, seq, !read_back);
    if (!read_back) {
        m_source_times.erase(m_source_times.begin(), m_source_times.upper_bound(seq));
        m_stats.pass_ms["publish"].add(std::chrono::duration<double, std::milli>(Clock::now() - t_publish).count());
        ++m_stats.rendered;
        const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - m_frame_start).count();
        m_stats.frame_ms.add(frame_ms);
        m_stats.frame_s_sum += frame_ms / 1000.0;
        return;
    }
    // The ring hands back a frame only when full; collect what has finished now so frames leave
    // in the tick that rendered them.
    std::vector<render::Frame> finished;
    if (auto oldest = renderer.readAsync(m_target, seq)) finished.push_back(std::move(*oldest));
    for (auto& f : renderer.collectReadbacks(m_target)) finished.push_back(std::move(f));
    publish(finished, frames);
    m_stats.pass_ms["publish"].add(std::chrono::duration<double, std::milli>(Clock::now() - t_publish).count());
    ++m_stats.rendered;
    const double frame_ms = std::chrono::duration<double, std::milli>(Clock::now() - m_frame_start).count();
    m_stats.frame_ms.add(frame_ms);
    m_stats.frame_s_sum += frame_ms / 1000.0;
}

void Display::samplePasses(const render::MapFrameStats& s) {
    ++m_stats.passes_sampled;
    const std::pair<const char*, double> passes[] = {
        {"uploads", s.uploads_ms},   {"terrain", s.terrain_ms},    {"buildings", s.buildings_ms},
        {"outlines", s.outlines_ms}, {"roads", s.roads_ms},        {"sv_roads", s.sv_roads_ms},
        {"route", s.route_ms},       {"labels", s.label_block_ms}, {"aura", s.aura_ms},
        {"glow", s.glow_ms},         {"marker", s.marker_ms}};
    double sum = 0.0;
    for (const auto& [name, ms] : passes) {
        m_stats.pass_ms[name].add(ms);
        sum += ms;
    }
    // The rest of the renderer's call: guidance overlay, binding, eviction.
    m_stats.pass_ms["other"].add(std::max(0.0, s.total_ms - sum));
}

void Display::collect(render::Renderer& renderer, ipc::FrameServer& frames) {
    auto done = renderer.collectReadbacks(m_target);
    publish(done, frames);
}

// Publishes finished readbacks, oldest first, with the CAN time behind each pose.
void Display::publish(std::vector<render::Frame>& finished, ipc::FrameServer& frames) {
    for (auto& done : finished) {
        if (done.sequence < m_first_complete) {
            ++m_stats.held_back;  // rendered before the map under the camera was drawable
            m_source_times.erase(m_source_times.begin(), m_source_times.upper_bound(done.sequence));
            continue;
        }
        if (m_attribution && done.image.width == m_profile.width && done.image.height == m_profile.height) {
            m_attribution->apply(done.image.rgba.data(), done.image.width * 4);
        }
        ipc::FrameView fv;
        fv.pixels = done.image.rgba.data();
        fv.width = done.image.width;
        fv.height = done.image.height;
        fv.format = ipc::PixelFormat::Rgba8;
        const auto it = m_source_times.find(done.sequence);
        const ipc::CanTime source = it != m_source_times.end() ? it->second.source : ipc::CanTime{};
        fv.source_time_ns = realtimeNs(source);
        if (it != m_source_times.end()) {
            fv.validity = it->second.annotation.validity;
            fv.meta = it->second.annotation.meta;
        }
        // routed by profile: same view and size, other style; one copy into each ring, after the readback's
        m_stats.cpu_copies += 1 + frames.publish(m_profile.name, fv);
        countPublished(source);
        m_source_times.erase(m_source_times.begin(), m_source_times.upper_bound(done.sequence));
    }
}

void Display::countPublished(ipc::CanTime source) {
    if (m_stats.published++ == 0) {
        m_stats.first_frame_s = std::chrono::duration<double>(Clock::now() - m_exec).count();
        m_log(Log::kInfo, "profile %s: first frame published %.0f ms after exec", m_profile.name.c_str(),
              m_stats.first_frame_s * 1000.0);
    }
    if (source != ipc::CanTime{}) {
        const double latency_ms = std::chrono::duration<double, std::milli>(ipc::CanClock::now() - source).count();
        m_stats.latency_ms.add(latency_ms);
        m_stats.latency_s_sum += latency_ms / 1000.0;
        ++m_stats.latency_count;
    }
}

// Start-up: frames wait for the tiles under the camera, and the frame server drops a client
// without a first frame after handshake_timeout_s. Its clients get a status meanwhile:
// "loading", how many tiles are still wanted, how many frames were held back. Each one restarts
// that timeout; the first frame ends them.
void Display::sendLoadingStatus(const std::vector<ipc::ActiveProfile>& active, ipc::FrameServer& frames,
                                Clock::time_point now) {
    if (m_stats.published > 0 && m_first_complete != kNone) return;  // after contextLost() again
    std::size_t clients = 0;
    for (const auto& a : active) {
        if (a.view == m_profile.stream_view && a.width == m_profile.width && a.height == m_profile.height)
            clients += a.clients;
    }
    const bool new_client = clients > m_status_clients;
    m_status_clients = clients;
    if (clients == 0 || (!new_client && now - m_last_status_sent < std::chrono::seconds(1))) return;
    m_last_status_sent = now;
    const nlohmann::ordered_json status = {
        // in the documented order, for people reading it
        {"state", "loading"},
        {"profile", m_profile.name},
        {"view", m_profile.stream_view},
        {"tiles_wanted", m_stats.tiles_wanted},
        {"held_back", m_stats.held_back},
        {"waited_ms", std::chrono::duration_cast<std::chrono::milliseconds>(now - m_started).count()},
        {"max_wait_ms", std::chrono::duration_cast<std::chrono::milliseconds>(kStartupTileWait).count()}};
    if (auto st = frames.publishStatus(m_profile.name, m_profile.width, m_profile.height,
                                       status.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace));
        !st) {
        m_log(Log::kWarning, "profile %s: %s", m_profile.name.c_str(), st.message().c_str());
    }
}

void Display::contextLost(ipc::FrameServer& frames, int resets, Clock::time_point now) {
    m_source_times.clear();
    m_first_complete = kNone;
    m_started = now;  // the wait for the tiles (kStartupTileWait) starts again
    m_last_status_sent = now;
    const nlohmann::ordered_json status = {
        {"state", "gpu_reset"}, {"profile", m_profile.name}, {"view", m_profile.stream_view}, {"resets", resets}};
    if (auto st = frames.publishStatus(m_profile.name, m_profile.width, m_profile.height, status.dump()); !st) {
        m_log(Log::kWarning, "profile %s: %s", m_profile.name.c_str(), st.message().c_str());
    }
}

}  // namespace navmap::daemon
