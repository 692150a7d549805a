// SPDX-License-Identifier: Apache-2.0
#include "display_scheduler.h"

#include <algorithm>
#include <utility>

#include "process_memory.h"

namespace navmap::daemon {

namespace {

render::RendererOptions rendererOptions(const DaemonConfig& config, const DisplayProfile& first,
                                        const std::filesystem::path& ortho_weights) {
    render::RendererOptions ro;
    ro.platform = render::parsePlatform(config.egl_platform).value_or(render::Platform::Auto);
    ro.width = first.width;
    ro.height = first.height;
    ro.msaa_samples = config.msaa;
    ro.max_tile_uploads_per_frame = 8;  // a burst of new tiles spreads over frames
    // GPU tiles kept: each costs about 0.45 MB (land-cover texture, terrain and road buffers), and
    // without a cap they pile up along a drive. A tile that any display drew in its latest frame
    // is never evicted (the renderer counts per target, not per render call), so the cap only
    // bounds the spare tiles kept for level-of-detail changes and turns. The three default views
    // draw 15-25 tiles each (57 together on the Andorra drive, fewer distinct ones); 16 + 8 per
    // profile, at least 32 (40 for three) re-uploads 106 tiles in 20 s of the replayed drive
    // against 102 with 48, for 4.5 MB less (docs/navmapd.md).
    ro.tile_resource_cache = config.gpu_tile_cache > 0
                                 ? config.gpu_tile_cache
                                 : std::max(32, 16 + 8 * static_cast<int>(config.profiles.size()));
    // Finished readbacks leave at once (collected after each render and polled while in flight).
    // 0 = the renderer's choice: on llvmpipe a frame is read straight into its image (glReadPixels
    // waits for the rasterization there even into a pixel-pack buffer, so buffers would only cost
    // width x height x 4 bytes each: 6.9 MB for the three default profiles); on a GPU two
    // pixel-pack buffers per target.
    ro.readback_ring = 0;
    // Synthetic orthoimages (seed 6.6.2): made at tile upload in bands of rows, at most this many
    // pixels of network work per map frame, so that no frame waits for a whole image: a 512 x 512
    // leaf-tile image takes 16 frames, about 14 ms of each on llvmpipe (docs/orthoimage.md,
    // docs/benchmarks/2026-11-26-ortho-gpu.md).
    ro.ortho_weights = ortho_weights.string();
    ro.ortho_pixels_per_frame = 16384;
    if (!config.shader_cache.empty()) ro.program_cache_dir = (config.shader_cache / "programs").string();
    ro.warm_up = true;  // made while the vehicle input starts on another thread (daemon.cpp)
    return ro;
}

}  // namespace

DisplayScheduler::DisplayScheduler(const DaemonConfig& config, Options options,
                                   const std::shared_ptr<map::TileCache>& cache, map::Projection projection,
                                   ipc::FrameServer& frames, Clock::time_point started, Log log)
    : m_options(std::move(options)),
      m_projection(projection),
      m_frames(frames),
      m_log(log),
      m_last_frame_done(Clock::now()) {
    // One renderer for every display: separate contexts cost a copy of every tile per display and
    // their own llvmpipe JIT code: 270-330 MB peak RSS with three profiles (docs/navmapd.md).
    for (const auto& p : config.profiles) {
        render::TargetHandle target;
        if (!m_renderer) {
            const render::RendererOptions ro = rendererOptions(config, p, m_options.ortho_weights);
            const auto t = Clock::now();
            m_renderer = m_options.noop_renderer ? render::Renderer::createNoop(ro) : render::Renderer::create(ro);
            const render::ProgramCacheStats programs = m_renderer->programCache();
            m_log(Log::kInfo, "start-up: renderer created in %.0f ms",
                  std::chrono::duration<double, std::milli>(Clock::now() - t).count());
            if (!programs.dir.empty() && !programs.problem.empty())
                m_log(Log::kWarning, "shader cache %s: off (%s)", programs.dir.c_str(), programs.problem.c_str());
            else if (!programs.dir.empty())
                m_log(Log::kInfo, "shader cache %s: %llu programs loaded, %llu compiled, %llu rejected",
                      programs.dir.c_str(), static_cast<unsigned long long>(programs.loaded),
                      static_cast<unsigned long long>(programs.compiled),
                      static_cast<unsigned long long>(programs.rejected));
            target = m_renderer->primaryTarget();
            logContext(m_renderer->device());
        } else {
            target = m_renderer->addTarget(p.width, p.height);
        }
        m_displays.push_back(std::make_unique<Display>(p, target, cache, makeAttribution(p), started,
                                                       m_options.exec == Clock::time_point{} ? started : m_options.exec,
                                                       m_log));
        m_displays.back()->setLoadPriority(static_cast<int>(m_displays.size()) - 1);
        m_pacing.emplace_back();
        const auto& dev = m_renderer->device();
        m_log(Log::kInfo, "profile %s %dx%d @ %.0f fps (%s): target %d, %s on %s, %s, MSAA %dx", p.name.c_str(),
              p.width, p.height, p.fps, p.stream_view.c_str(), target.id(), dev.backend.c_str(), dev.platform.c_str(),
              dev.renderer.c_str(), dev.msaa_samples);
    }
}

void DisplayScheduler::logContext(const render::DeviceInfo& dev) const {
    // The context's version and what it cannot do (docs/gles-profile.md): an ECU's ES 3.0 driver
    // says here which features navmapd drew without.
    if (dev.backend != "gles") {
        m_log(Log::kInfo, "GL context: none (%s renderer)", dev.backend.c_str());
        return;
    }
    std::string off;
    for (const auto& f : dev.features_off) off += (off.empty() ? "" : "; ") + f;
    m_log(Log::kInfo, "GL context: OpenGL ES %d.%d (%s), %s; features off: %s", dev.gles_major, dev.gles_minor,
          dev.version.c_str(), dev.renderer.c_str(), off.empty() ? "none" : off.c_str());
    const render::DmabufCapability& d = dev.dmabuf;
    if (d.available)
        m_log(Log::kInfo, "dma-buf export: on, buffers from %s (sync: %s): clients may ask for payload dmabuf",
              d.drm_node.c_str(), d.native_fence_sync ? "native fences" : "glFinish");
    else
        m_log(Log::kInfo, "dma-buf export: off (%s): frames go through shared memory", d.reason.c_str());
}

std::string DisplayScheduler::dmabufRefusal(const render::DmabufCapability& capability) {
    return capability.available ? std::string() : capability.reason;
}

std::unique_ptr<AttributionOverlay> DisplayScheduler::makeAttribution(const DisplayProfile& p) {
    if (!p.attribution) return nullptr;
    if (!m_overlay_text) m_overlay_text = std::make_unique<render::text::TextEngine>();
    return std::make_unique<AttributionOverlay>(*m_overlay_text, AttributionOverlay::kOsmAttribution, p.width,
                                                p.height);
}

void DisplayScheduler::rebase(const map::Projection& frame) {
    m_projection = frame;
    for (const auto& d : m_displays) d->rebase();
}

DisplayScheduler::Clock::time_point DisplayScheduler::tick(Clock::time_point now, const PoseSource& poses,
                                                           const FrameContext& context) {
    const auto active = m_frames.activeProfiles();
    m_rendering_wanted = m_options.render_all || !active.empty();
    Clock::time_point next_wake = now + std::chrono::milliseconds(50);
    for (auto& d : m_displays) d->sendLoadingStatus(active, m_frames, now);
    // Start-up, cluster first: a watched display listed earlier that has rendered nothing yet
    // holds back the first frames of those after it (Display::holdFirstFrame).
    bool earlier_starting = false, previous_wanted = false;
    for (std::size_t i = 0; i < m_displays.size(); ++i) {
        Display& d = *m_displays[i];
        Pacing& pacing = m_pacing[i];
        // After the previous display's draw of this tick: its first frame frees the next one now.
        if (i > 0) earlier_starting = earlier_starting || (previous_wanted && !m_displays[i - 1]->started());
        const bool wanted = m_options.render_all ||
                            std::any_of(active.begin(), active.end(),
                                        [&](const ipc::ActiveProfile& a) { return a.profile == d.profile().name; });
        previous_wanted = wanted;
        const bool hold = earlier_starting;
        if (now < pacing.next_due) {
            next_wake = std::min(next_wake, pacing.next_due);
            continue;
        }
        pacing.next_due = std::max(pacing.next_due + std::chrono::duration_cast<Clock::duration>(
                                                         std::chrono::duration<double>(1.0 / d.profile().fps)),
                                   now);
        next_wake = std::min(next_wake, pacing.next_due);
        if (!wanted) {
            d.skipIdle();  // nobody watches this display: render nothing
            continue;
        }
        d.holdFirstFrame(hold);
        if (d.draw(*m_renderer, poses, context, m_projection)) {
            warnFlatTiles();
            const auto mine = std::find_if(active.begin(), active.end(), [&](const ipc::ActiveProfile& a) {
                return a.profile == d.profile().name && a.width == d.profile().width && a.height == d.profile().height;
            });
            d.finishFrame(*m_renderer, m_frames, now, mine != active.end() ? &*mine : nullptr);
        }
        noticeContextResets(now);
        m_last_frame_done = Clock::now();  // a start-up tick that only requested tiles is progress too
    }
    // Readbacks still in flight: the rasterizer finishes them on its own threads while the loop
    // renders the next displays or sleeps. Send each as soon as it is done (polled every few
    // milliseconds, never waited for) instead of at that display's next tick, which would add a
    // frame interval to its CAN -> frame latency.
    for (auto& d : m_displays) {
        if (!d->inFlight()) continue;
        d->collect(*m_renderer, m_frames);
        if (d->inFlight()) next_wake = std::min(next_wake, Clock::now() + std::chrono::milliseconds(3));
    }
    return next_wake;
}

void DisplayScheduler::noticeContextResets(Clock::time_point now) {
    const int resets = m_renderer->device().context_resets;
    if (resets == m_context_resets) return;
    m_context_resets = resets;
    m_log(Log::kWarning, "GL context lost or reset (%d so far): made anew; the displays wait for their tiles again",
          resets);
    for (auto& d : m_displays) d->contextLost(m_frames, resets, now);
}

void DisplayScheduler::warnFlatTiles() {
    // Said once by the renderer, when the orthoimage ground is first wanted and cannot be made.
    if (const std::string& problem = m_renderer->mapStats().ortho_problem; !problem.empty()) {
        m_log(Log::kErr, "%s", problem.c_str());
        m_ortho_problem = problem;
    }
    for (const auto& flat : m_renderer->mapStats().new_flat_tiles) {
        if (m_warned_flat.insert(flat.id.key()).second) {
            m_log(Log::kWarning, "tile %s: %.0f%% of its area has no elevation data and renders flat",
                  flat.id.toString().c_str(), 100.0 * (1.0 - flat.coverage));
        }
    }
}

void DisplayScheduler::reconfigure(const std::vector<DisplayProfile>& profiles) {
    for (std::size_t i = 0; i < m_displays.size(); ++i) {
        Display& d = *m_displays[i];
        const auto p = findProfile(profiles, d.profile().name);
        if (p && p->width == d.profile().width && p->height == d.profile().height) {
            d.reconfigure(*p, p->attribution != d.profile().attribution ? makeAttribution(*p) : nullptr);
            m_pacing[i].next_due = Clock::now();  // the new rate applies from the next tick
        } else if (p) {
            m_log(Log::kWarning, "reload: profile %s: a new size (%dx%d) needs a restart; keeping %dx%d",
                  d.profile().name.c_str(), p->width, p->height, d.profile().width, d.profile().height);
        }
    }
}

bool DisplayScheduler::framesFlowing(double max_frame_s) const {
    return !m_rendering_wanted || std::chrono::duration<double>(Clock::now() - m_last_frame_done).count() < max_frame_s;
}

void DisplayScheduler::logSummary() const {
    const ProcessMemory mem = processMemory();
    m_log(Log::kNotice, "peak RSS %.1f MiB (%zu profiles, one renderer with %zu targets)",
          static_cast<double>(mem.peak) / (1 << 20), m_displays.size(),
          m_renderer ? m_renderer->targetCount() : std::size_t{0});
    for (const auto& d : m_displays) {
        const DisplayStats& s = d->stats();
        m_log(Log::kInfo,
              "profile %s: %llu frames rendered, %llu published, frame p50 %.1f ms p99 %.1f ms, latency p50 %.1f ms "
              "p99 %.1f ms, %llu tile uploads",
              d->profile().name.c_str(), static_cast<unsigned long long>(s.rendered),
              static_cast<unsigned long long>(s.published), s.frame_ms.quantile(0.5), s.frame_ms.quantile(0.99),
              s.latency_ms.quantile(0.5), s.latency_ms.quantile(0.99),
              static_cast<unsigned long long>(s.tiles_uploaded));
    }
}

}  // namespace navmap::daemon
