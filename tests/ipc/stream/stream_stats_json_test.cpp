// SPDX-License-Identifier: Apache-2.0
// frameServerStatsJson, the one "stream" object of get_status and GET /status: every key with the
// field it comes from (each field a different value, so a swapped field shows).

#include "navmap/ipc/stream/frame_server_stats_json.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

namespace {

using navmap::ipc::FrameServerStats;
using navmap::ipc::frameServerStatsJson;

TEST(FrameServerStatsJson, EveryKeyCarriesItsOwnCounter) {
    FrameServerStats s;
    s.clients = 1;
    s.shm_clients = 2;
    s.tcp_clients = 3;
    s.mjpeg_clients = 4;
    s.rings = 5;
    s.rings_idle = 6;
    s.rings_reused = 7;
    s.published = 8;
    s.frames_sent = 9;
    s.statuses_sent = 10;
    s.frames_dropped = 11;
    s.stall_disconnects = 12;
    s.handshake_errors = 13;
    s.handshake_timeouts = 14;
    s.first_frame_timeouts = 15;
    s.refused_peer = 16;
    s.refused_transport_full = 17;
    s.refused_uid_full = 18;
    s.refused_address_full = 19;
    s.refused_not_rendered = 20;
    s.refused_ring_memory = 21;
    s.refused_host = 22;
    s.refused_token = 23;
    s.ring_bytes = 24;
    s.dmabuf_clients = 25;
    s.dmabuf_frames_sent = 26;
    s.dmabuf_fds_sent = 27;
    s.publish_ms_last = 2.5;
    s.last_error = "tcp#7: handshake: unknown key \"x\"";
    EXPECT_EQ(frameServerStatsJson(s).dump(),
              R"({"clients":1,"dmabuf_clients":25,"dmabuf_fds_sent":27,"dmabuf_frames_sent":26,)"
              R"("frames_dropped":11,"frames_sent":9,"handshake_errors":13,)"
              R"("last_error":"tcp#7: handshake: unknown key \"x\"","mjpeg_clients":4,"publish_ms_last":2.5,)"
              R"("published":8,"refusals":{"address_full":19,"http_host":22,"http_token":23,"not_rendered":20,)"
              R"("peer":16,"ring_memory":21,"transport_full":17,"uid_full":18},"ring_bytes":24,"rings":5,)"
              R"("rings_idle":6,"rings_reused":7,"shm_clients":2,"stall_disconnects":12,"statuses_sent":10,)"
              R"("tcp_clients":3,"timeouts":{"first_frame":15,"handshake":14}})");
}

}  // namespace
