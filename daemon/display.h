// SPDX-License-Identifier: Apache-2.0
#pragma once
// Display: one display profile as navmapd renders it: its offscreen target in the shared
// renderer, its tile selection (MapView), camera rig and attribution overlay, the frames it has
// in flight (sequence -> CAN time behind the pose, for latency) and its counters. It renders a
// frame when the DisplayScheduler says so, publishes finished readbacks to the frame server, and
// holds its frames back until one shows the map under its camera (docs/navmapd.md "Start-up").
// Render thread only.

#include <chrono>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <vector>

#include "attribution_overlay.h"
#include "frame_annotator.h"
#include "log.h"
#include "navmap/ipc/control/control_state.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/render/camera_rig.h"
#include "navmap/render/map_view.h"
#include "navmap/render/renderer.h"
#include "pose_source.h"
#include "profiles.h"
#include "route_guidance.h"
#include "sample_window.h"
#include "street_bar_hold.h"

namespace navmap::daemon {

/// A display's counters (status, /metrics, the exit summary).
struct DisplayStats {
    std::uint64_t rendered = 0, published = 0;
    std::uint64_t skipped_idle = 0;                 ///< due frames not rendered: nobody watched
    SampleWindow frame_ms, latency_ms;              ///< the last 600 frames
    double frame_s_sum = 0.0, latency_s_sum = 0.0;  ///< since the start (/metrics summaries)
    std::uint64_t latency_count = 0;
    std::size_t tiles_drawn = 0, tiles_pending = 0;  ///< last frame
    std::size_t tiles_wanted = 0;                    ///< last frame: tiles the view still waits for
    std::uint64_t tiles_uploaded = 0;                ///< GPU tile uploads of this display's frames
    std::uint64_t held_back = 0;                     ///< frames not published while the map loaded
    /// Frames handed out as exported dma-bufs (docs/frame-protocol.md "dma-buf frames"), and
    /// those not, because every buffer was still held by a client.
    std::uint64_t dmabuf_published = 0, dmabuf_busy = 0;
    /// Pixel copies the CPU made for this profile's frames: one readback per frame read back,
    /// one per ring it was written into; a dma-buf frame costs none (navmap_frame_cpu_copies_total).
    std::uint64_t cpu_copies = 0;
    /// Where the frame time goes (get_status "passes", navmap_pass_seconds), ms per pass name:
    /// every frame's `select` (camera, tiles), `render` (the renderer's call) and `publish`
    /// (readbacks to the frame server); and, of one frame in kPassSampleEvery, the renderer's
    /// passes timed with a glFinish after each (uploads, terrain, buildings, outlines, roads,
    /// sv_roads, route, labels, aura, glow, marker, other).
    std::map<std::string, SampleWindow> pass_ms;
    std::uint64_t passes_sampled = 0;  ///< frames whose renderer passes were timed
    /// Seconds from the process's exec to its first published frame; negative until then
    /// (navmap_first_frame_seconds, `first_frame_s` in get_status).
    double first_frame_s = -1.0;
};

/// What all displays' frames of one tick share.
struct FrameContext {
    const ipc::ViewState* view_state = nullptr;  ///< the control socket's view settings (may be null)
    render::MapStyle style;
    const render::RouteGeometry* route = nullptr;
    double route_progress_m = 0.0;
    const GuidanceSnapshot* guidance = nullptr;  ///< arrows and the next-turn panel; null: none
    bool labels = true;
    FrameHealth health;  ///< for each frame's validity and metadata (FrameAnnotator)
};

class Display {
public:
    using Clock = std::chrono::steady_clock;
    /// One frame in this many has its renderer passes timed (DisplayStats::pass_ms): about once
    /// a second at 30 fps, so the glFinish after each pass costs little.
    static constexpr std::uint64_t kPassSampleEvery = 30;

    /// `target`: this display's offscreen target in the shared renderer; `started`: the daemon's
    /// start (the start-up wait counts from there); `exec`: the process's start (the first
    /// frame's time counts from there).
    Display(DisplayProfile profile, render::TargetHandle target, std::shared_ptr<map::TileCache> cache,
            std::unique_ptr<AttributionOverlay> attribution, Clock::time_point started, Clock::time_point exec,
            Log log);

    [[nodiscard]] const DisplayProfile& profile() const { return m_profile; }
    [[nodiscard]] render::TargetHandle target() const { return m_target; }
    [[nodiscard]] const DisplayStats& stats() const { return m_stats; }
    [[nodiscard]] bool hasAttribution() const { return m_attribution != nullptr; }
    /// False until a frame showed the map under the camera (or the start-up wait ran out).
    [[nodiscard]] bool mapReady() const { return m_first_complete != kNone; }
    /// True once a frame was rendered (for the start-up order: Display::holdFirstFrame).
    [[nodiscard]] bool started() const { return m_stats.rendered > 0; }
    /// Frames rendered whose readback has not been published yet.
    [[nodiscard]] bool inFlight() const { return !m_source_times.empty(); }
    /// The pose of the last rendered frame (tests: every display stands the vehicle on the same ground).
    [[nodiscard]] const render::VehiclePose& lastPose() const { return m_last_pose; }

    /// Reload: the settings of `p` (same size); `attribution` replaces the overlay when the
    /// profile's attribution setting changed.
    void reconfigure(const DisplayProfile& p, std::unique_ptr<AttributionOverlay> attribution);
    void skipIdle() { ++m_stats.skipped_idle; }
    /// The tile loader's queue for this display's tiles: lower loads first (the scheduler gives
    /// the profiles their configured order, the cluster first).
    void setLoadPriority(int queue) { m_map_view.setLoadQueue(queue); }
    /// Start-up, cluster first: while set, a display whose map is not ready yet renders no first
    /// frame even when its tiles are resident (its uploads, shader JIT and rasterization would
    /// take the CPU that a display listed before it needs for its own first frame). Bounded by
    /// the same start-up wait as the tiles. The scheduler sets it before every draw().
    void holdFirstFrame(bool hold) { m_hold_first = hold; }

    /// The daemon re-centred its map frame: forgets what it keeps in the old one (the HUD's
    /// junction roads).
    void rebase();
    /// Renders one frame into this display's target with the pose of this moment. At start-up,
    /// while the tiles under the camera are still loading, it only selects and requests them and
    /// renders nothing (the frame would be held back): returns false then, and finishFrame() is
    /// not called for it.
    bool draw(render::Renderer& renderer, const PoseSource& poses, const FrameContext& context,
              const map::Projection& projection);
    /// After draw(): numbers the frame, hands it to the dma-buf clients (exported, no copy) and
    /// starts its readback for the others, publishes the readbacks that have finished, times the
    /// frame. `tick`: when the loop's tick began (the start-up wait is measured to it). `active`:
    /// this profile's clients (null: none, e.g. rendering for tests with render_all): without
    /// clients that need pixels no readback is made.
    void finishFrame(render::Renderer& renderer, ipc::FrameServer& frames, Clock::time_point tick,
                     const ipc::ActiveProfile* active);
    /// Publishes readbacks finished since (polled while frames are in flight).
    void collect(render::Renderer& renderer, ipc::FrameServer& frames);
    /// Until the first frame is published, the display's stream clients get a loading status: at
    /// once for a new client, then about once a second.
    void sendLoadingStatus(const std::vector<ipc::ActiveProfile>& active, ipc::FrameServer& frames,
                           Clock::time_point now);
    /// The renderer made a new GL context (`resets` so far): readbacks in flight are gone, the
    /// clients get a "gpu_reset" status at once, and frames wait again, as at start-up, for the
    /// tiles under the camera, with loading statuses meanwhile.
    void contextLost(ipc::FrameServer& frames, int resets, Clock::time_point now);

private:
    /// The guidance's arrows (every view) and, in the HUD, its next-turn panel and corridor.
    void addGuidance(render::MapFrame& frame, const GuidanceSnapshot& guidance, const render::RouteGeometry* route,
                     bool hud);
    /// The roads within kJunctionRoadsM of the junction on the frame's tiles (cached while both stay).
    const std::vector<std::vector<glm::dvec3>>& junctionRoads(const render::MapFrame& frame, glm::dvec2 junction);
    static constexpr double kArrowBeforeM = 40.0;    ///< arrow shaft along the incoming road
    static constexpr double kArrowAfterM = 25.0;     ///< and past the junction (or roundabout exit)
    static constexpr double kJunctionRoadsM = 60.0;  ///< HUD: roads drawn within this of the junction

    static constexpr std::uint64_t kNone = ~std::uint64_t{0};
    void publish(std::vector<render::Frame>& finished, ipc::FrameServer& frames);
    /// The frame `seq` just drawn, copied on the GPU into a free exported buffer, to the dma-buf
    /// clients (display_dmabuf.cpp). `counted`: this publication is the frame's (no readback).
    void exportDmabuf(render::Renderer& renderer, ipc::FrameServer& frames, std::uint64_t seq, bool counted);
    /// A frame header's source time: the CAN time behind its pose (CLOCK_REALTIME ns).
    static std::int64_t realtimeNs(ipc::CanTime t) {
        return std::chrono::duration_cast<std::chrono::nanoseconds>(t.time_since_epoch()).count();
    }
    /// A frame went out: published count, first-frame log, CAN-to-frame latency.
    void countPublished(ipc::CanTime source);
    /// Adds a profiled frame's pass times to DisplayStats::pass_ms.
    void samplePasses(const render::MapFrameStats& s);

    DisplayProfile m_profile;
    std::vector<std::vector<glm::dvec3>> m_roads;  // junctionRoads(): the HUD's corridor at the junction
    glm::dvec2 m_roads_junction{std::numeric_limits<double>::quiet_NaN()};
    std::vector<const map::Tile*> m_roads_tiles;
    render::TargetHandle m_target;
    Clock::time_point m_started;
    Clock::time_point m_exec;
    Log m_log;
    render::MapView m_map_view;
    render::CameraRig m_rig;
    std::unique_ptr<AttributionOverlay> m_attribution;
    render::Image m_attribution_pixels;  // m_attribution premultiplied, for exported frames (made once)
    std::uint64_t m_attribution_id = 0;  // changes with m_attribution (the renderer's upload key)
    // The frame being drawn (draw -> finishFrame).
    Clock::time_point m_frame_start{}, m_last_frame{};
    ipc::CanTime m_frame_source{};
    FrameAnnotation m_frame_annotation;  // validity and metadata of the frame being drawn
    FrameAnnotator m_annotator;
    StreetBarHold m_street_hold;  // the street the bar shows
    render::VehiclePose m_last_pose;
    std::uint64_t m_sequence = 0;
    /// A frame rendered and not yet published: the CAN time behind its pose, its annotation.
    struct InFlight {
        ipc::CanTime source{};
        FrameAnnotation annotation;
    };
    std::map<std::uint64_t, InFlight> m_source_times;  // sequence -> what goes with the frame
    // Start-up: no frame leaves before one shows the camera's tiles at their level of detail,
    // uploaded (not sky, not a coarse parent). Frames before it are dropped.
    std::uint64_t m_first_complete = kNone;
    Clock::time_point m_last_status_sent{};
    std::size_t m_status_clients = 0;
    DisplayStats m_stats;
    bool m_hold_first = false;  // holdFirstFrame()
};

}  // namespace navmap::daemon
