// SPDX-License-Identifier: Apache-2.0
#pragma once
// DisplayScheduler: which display renders when. It owns the one renderer all display profiles
// share (one EGL context, one copy of each tile's GPU resources; each display renders into its own
// offscreen target) and the displays, paces each at its profile's frame rate, renders a display
// only while a client watches it (or with render_all), and publishes readbacks as soon as they
// finish. The render loop calls tick(), which never waits for I/O. Render thread only.

#include <chrono>
#include <cstdint>
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "config.h"
#include "display.h"
#include "log.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap/map/tile_cache.h"
#include "navmap/render/renderer.h"
#include "navmap/render/text/text_engine.h"
#include "pose_source.h"

namespace navmap::daemon {

class DisplayScheduler {
public:
    using Clock = std::chrono::steady_clock;

    struct Options {
        bool noop_renderer = false;  ///< no GL (tests of the loop itself)
        bool render_all = false;     ///< render profiles without clients too
        /// The orthoimage network's weights (RendererOptions::ortho_weights); empty: none.
        std::filesystem::path ortho_weights;
        /// The process's start (processStartTime()): first-frame times count from it. Default:
        /// `started`.
        Clock::time_point exec{};
    };

    /// Creates the renderer and one display per configured profile (logged); throws
    /// std::runtime_error when the renderer cannot be created.
    DisplayScheduler(const DaemonConfig& config, Options options, const std::shared_ptr<map::TileCache>& cache,
                     map::Projection projection, ipc::FrameServer& frames, Clock::time_point started, Log log);

    /// One tick of the loop at `now`: loading statuses to waiting clients, then every display whose
    /// frame is due and watched renders (with the pose of its own moment from `poses`), then the
    /// readbacks in flight are collected. Returns when the loop should wake up next.
    Clock::time_point tick(Clock::time_point now, const PoseSource& poses, const FrameContext& context);

    /// The daemon re-centred its map frame on the vehicle: cameras use `frame` from now on and the
    /// displays forget what they kept in the old one.
    void rebase(const map::Projection& frame);

    /// Reload: each display takes the new settings of its profile in `profiles` (a profile whose
    /// size changed keeps running as it is, with a warning); new rates apply from the next tick.
    void reconfigure(const std::vector<DisplayProfile>& profiles);

    /// Healthy for the watchdog: frames keep completing within `max_frame_s`, or nobody needs any.
    [[nodiscard]] bool framesFlowing(double max_frame_s) const;
    [[nodiscard]] const std::vector<std::unique_ptr<Display>>& displays() const { return m_displays; }
    /// Why the orthoimage ground cannot be drawn (weights missing or unusable), as logged; empty
    /// while none was found (docs/orthoimage.md "In the map").
    [[nodiscard]] const std::string& orthoProblem() const { return m_ortho_problem; }
    /// Whether the renderer could export frames as dma-bufs, and why not (probed at start-up;
    /// navmapd serves shm frames either way: docs/frame-protocol.md "dma-buf frames").
    [[nodiscard]] const render::DmabufCapability& dmabuf() const { return m_renderer->device().dmabuf; }
    /// Why navmapd refuses dma-buf frame requests (the frame server's reason); empty: it accepts them.
    [[nodiscard]] static std::string dmabufRefusal(const render::DmabufCapability& capability);
    /// GL contexts lost and made anew so far (render::DeviceInfo::context_resets, as told to the displays).
    [[nodiscard]] int contextResets() const { return m_context_resets; }
    /// The exit summary: peak memory, then a line per display.
    void logSummary() const;

private:
    struct Pacing {
        Clock::time_point next_due{};
    };
    std::unique_ptr<AttributionOverlay> makeAttribution(const DisplayProfile& p);
    /// Logs the renderer's GL context: version, renderer, the features turned off on it.
    void logContext(const render::DeviceInfo& dev) const;
    void warnFlatTiles();
    /// After a draw: when the renderer made a new GL context, says so and tells every display.
    void noticeContextResets(Clock::time_point now);

    Options m_options;
    map::Projection m_projection;
    ipc::FrameServer& m_frames;
    Log m_log;
    std::unique_ptr<render::Renderer> m_renderer;
    // The attribution overlays are laid out with the label text engine (CPU only): one for all
    // displays that show it, made when the first one needs it.
    std::unique_ptr<render::text::TextEngine> m_overlay_text;
    std::vector<std::unique_ptr<Display>> m_displays;
    std::vector<Pacing> m_pacing;           // parallel to m_displays
    std::set<std::uint64_t> m_warned_flat;  // tiles reported as lacking elevation data
    std::string m_ortho_problem;            // orthoProblem()
    bool m_rendering_wanted = true;
    int m_context_resets = 0;  // DeviceInfo::context_resets already told
    Clock::time_point m_last_frame_done;
};

}  // namespace navmap::daemon
