// SPDX-License-Identifier: Apache-2.0
#include "status_reporter.h"

namespace navmap::daemon {

void StatusReporter::update(Clock::time_point now, const EstimatedPose& pose) {
    if (now - m_last <= std::chrono::seconds(1)) return;
    m_last = now;
    StatusSample s;
    s.uptime_s = std::chrono::duration<double>(now - m_started).count();
    s.config_path = m_parts.reloader.path();
    s.config_style = ipc::mapStyleName(configuredStyle(m_parts.config));
    const DayNight& dn = m_parts.day_night;
    s.style = {ipc::mapStyleName(dn.requested()), dn.night(), styleReasonName(dn.reason()), dn.weight(),
               dn.sunElevationDeg()};
    s.ortho_problem = m_parts.displays.orthoProblem();
    s.dmabuf = m_parts.displays.dmabuf();
    s.reloads = m_parts.reloader.reloads();
    s.reload_errors = m_parts.reloader.errors();
    s.last_reload_error = m_parts.reloader.lastError();
    s.input = m_parts.input.stats();
    s.road_graph = m_parts.road_graph;
    s.pose = pose;
    s.route_id = m_parts.route.id();
    s.route_driven_m = m_parts.route.drivenM();
    s.displays = &m_parts.displays.displays();
    s.stream = m_parts.frames.stats();
    s.control = m_parts.control.stats();
    s.cache = m_parts.cache.metrics();
    const map::Projection& frame = m_parts.frame.frame();
    s.frame = {frame.originLat(), frame.originLon(), m_parts.frame.epoch(),
               pose.valid ? FrameRecentring::scaleError(frame, pose.x, pose.y) : 0.0};
    if (pose.valid) frame.reverse({pose.x, pose.y}, s.frame.vehicle_lat, s.frame.vehicle_lon);
    if (const auto& set = m_parts.scene.set; set && set->storeCount() > 1) {
        for (std::size_t i = 0; i < set->storeCount(); ++i)
            s.stores.push_back({set->store(i).path().string(), set->store(i).info().tile_count, set->loads(i)});
    } else {
        s.stores.push_back(
            {m_parts.scene.store->path().string(), m_parts.scene.store->info().tile_count, s.cache.loads});
    }
    s.memory = processMemory();
    m_status.publish(s);
    m_metrics.update(s);
    m_systemd.status(DaemonStatus::systemdLine(s));
}

}  // namespace navmap::daemon
