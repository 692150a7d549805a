// SPDX-License-Identifier: Apache-2.0
#include "server_options.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "navmap/ipc/net/socket_access.h"

namespace navmap::daemon {

ipc::ControlServerConfig controlServerConfig(const DaemonConfig& config) {
    ipc::ControlServerConfig ccfg;
    ccfg.socket_path = config.control_socket.string();
    ccfg.socket_mode = static_cast<mode_t>(config.control_mode);
    for (auto uid : config.control_uids) ccfg.allowed_uids.push_back(static_cast<uid_t>(uid));
    for (auto gid : config.control_gids) ccfg.allowed_gids.push_back(static_cast<gid_t>(gid));
    if (!config.control_group.empty()) {
        auto gid = ipc::resolveGroup(config.control_group, "control.group");
        if (!gid) throw std::runtime_error(gid.error().message);
        ccfg.socket_group = gid.value();
    }
    ccfg.idle_timeout = std::chrono::milliseconds(std::llround(config.control_idle_timeout_s * 1000.0));
    ccfg.max_clients_per_uid = static_cast<std::size_t>(config.control_max_clients_per_uid);
    ccfg.max_subscribers_per_uid = static_cast<std::size_t>(config.control_max_subscribers_per_uid);
    for (auto uid : config.control_privileged_uids) ccfg.privileged_uids.push_back(static_cast<uid_t>(uid));
    return ccfg;
}

ipc::FrameServerOptions frameServerOptions(const DaemonConfig& config) {
    ipc::FrameServerOptions fopt;
    fopt.unix_path = config.frame_socket.string();
    if (!config.stream_group.empty()) {
        auto gid = ipc::resolveGroup(config.stream_group, "stream.group");
        if (!gid) throw std::runtime_error(gid.error().message);
        fopt.unix_group = gid.value();
    }
    for (auto uid : config.stream_uids) fopt.allowed_peers.uids.push_back(static_cast<uid_t>(uid));
    for (auto gid : config.stream_gids) fopt.allowed_peers.gids.push_back(static_cast<gid_t>(gid));
    fopt.max_clients_per_transport = static_cast<std::size_t>(config.max_clients_per_transport);
    fopt.max_clients_per_uid = static_cast<std::size_t>(config.max_clients_per_uid);
    fopt.max_clients_per_address = static_cast<std::size_t>(config.max_clients_per_address);
    fopt.ring_memory_bytes = config.ring_memory_mb << 20;
    // Only what the daemon renders is served: its profiles' views and sizes.
    double slowest_fps = 1000.0;
    for (const auto& p : config.profiles) {
        fopt.rendered_profiles.push_back({p.name, p.stream_view, p.width, p.height});
        slowest_fps = std::min(slowest_fps, p.fps);
    }
    // A first frame comes within a frame period of the slowest profile (plus its render), so the
    // timeout is never shorter than two of those periods.
    fopt.handshake_timeout = std::chrono::milliseconds(
        static_cast<std::int64_t>(std::max(config.handshake_timeout_s, 2.0 / slowest_fps) * 1000));
    fopt.bind_address = config.http_address;
    fopt.tcp_port = config.tcp_port > 0 ? config.tcp_port : -1;
    fopt.http_port = config.http_port > 0 ? config.http_port : -1;
    fopt.http_token = config.http_token;
    fopt.stall_timeout = std::chrono::milliseconds(static_cast<int>(config.client_timeout_s * 1000));
    fopt.mjpeg_profile = config.profiles.front().name;  // the page's first stream: a profile rendered here
    // Two slots per ring (double buffering): each costs a frame of shared memory (6.6 MB for the
    // three default profiles), and the seqlock never lets a client keep a frame that was
    // overwritten; a client still copying when the frame after next arrives (one frame period,
    // 33 ms at 30 fps, for a copy of about a millisecond) takes the newest one instead.
    fopt.ring_slots = 2;
    return fopt;
}

}  // namespace navmap::daemon
