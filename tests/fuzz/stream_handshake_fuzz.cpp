// SPDX-License-Identifier: Apache-2.0
// libFuzzer target: everything a stream client can send or a server can answer before pixels:
// the JSON handshake line, the server's JSON reply (read by the client against a shm and a raw
// request), the HTTP request head, the 80-byte frame header with the error or status text
// after it, and the same bytes as a frame's metadata block (docs/frame-protocol.md "Metadata block")
// and as a dma-buf frame's 48-byte block ("dma-buf frames").
// Built with -DNAVMAP_WITH_FUZZ=ON (clang); stream_unit_tests compiles it too (NAVMAP_FUZZ_NO_MAIN)
// and runs navmapFuzzStreamHandshake() on a corpus of broken inputs.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "navmap/ipc/client/dmabuf_block.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_meta.h"
#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_profile.h"
#include "navmap/ipc/stream/stream_http_request.h"

int navmapFuzzStreamHandshake(const std::uint8_t* data, std::size_t size) {
    const std::string_view text(reinterpret_cast<const char*>(data), size);
    auto req = navmap::ipc::parseStreamRequest(text);
    if (req.ok()) {
        // Whatever was accepted must format and parse back to the same request.
        auto again = navmap::ipc::parseStreamRequest(navmap::ipc::formatStreamRequest(req.value()));
        const auto& a = req.value().profile;
        if (!again.ok() || again.value().profile.width != a.width || again.value().profile.height != a.height ||
            again.value().profile.fps != a.fps || again.value().profile.view != a.view ||
            again.value().profile.format != a.format || again.value().profile.name != a.name ||
            again.value().payload != req.value().payload) {
            __builtin_trap();
        }
    }
    // The same bytes as a server's reply: whatever the client accepts is what it asked for, and a
    // shm ring's size is the layout of that profile (the client maps that many bytes).
    for (const auto payload : {navmap::ipc::StreamPayload::Shm, navmap::ipc::StreamPayload::Raw}) {
        navmap::ipc::StreamRequest asked;
        asked.profile = *navmap::ipc::defaultStreamProfile("hud");
        asked.payload = payload;
        auto reply = navmap::ipc::parseStreamReply(text, asked);
        if (!reply.ok() || !reply.value().accepted) {
            continue;
        }
        const auto& r = reply.value();
        if (r.profile.width != asked.profile.width || r.profile.height != asked.profile.height ||
            r.profile.format != asked.profile.format) {
            __builtin_trap();
        }
        if (payload == navmap::ipc::StreamPayload::Shm &&
            (r.ring_slots < 1 || r.ring_slots > navmap::ipc::kMaxRingSlots ||
             r.ring_total_bytes !=
                 navmap::ipc::FrameRingLayout::make(r.ring_slots, 800, 240, r.profile.format).total_bytes)) {
            __builtin_trap();
        }
    }
    // A reply accepting dma-bufs grants what was asked for, and no ring.
    navmap::ipc::StreamRequest dmabuf;
    dmabuf.profile = *navmap::ipc::defaultStreamProfile("hud");
    dmabuf.payload = navmap::ipc::StreamPayload::Dmabuf;
    if (auto reply = navmap::ipc::parseStreamReply(text, dmabuf); reply.ok() && reply.value().accepted) {
        if (reply.value().profile.width != 800 || reply.value().profile.height != 240 ||
            reply.value().ring_slots != 0) {
            __builtin_trap();
        }
    }
    // The same bytes as a dma-buf block: what decodes encodes back to the same bytes, and its
    // rows fit the stride the client maps.
    if (auto block = navmap::ipc::decodeDmabufBlock(data, size); block.ok()) {
        const auto& b = block.value();
        const auto bytes = navmap::ipc::encodeDmabufBlock(b);
        if (b.stride < b.width * 4U || b.planes != 1 || !std::equal(bytes.begin(), bytes.end(), data)) {
            __builtin_trap();
        }
    }
    (void)navmap::ipc::parseStreamHttpRequest(text);
    auto header = navmap::ipc::decodeFrameHeader(data, size);
    if (header.ok()) {
        const auto bytes = navmap::ipc::encodeFrameHeader(header.value());
        auto again = navmap::ipc::decodeFrameHeader(bytes.data(), bytes.size());
        if (!again.ok() || again.value().sequence != header.value().sequence ||
            again.value().payload_bytes != header.value().payload_bytes) {
            __builtin_trap();
        }
        const auto kind = header.value().kind;
        if (kind == navmap::ipc::FrameKind::Error || kind == navmap::ipc::FrameKind::Status) {
            const std::size_t have = size - navmap::ipc::kFrameHeaderBytes;
            const std::size_t n = have < header.value().payload_bytes ? have : header.value().payload_bytes;
            (void)navmap::ipc::validateTextPayload(kind, data + navmap::ipc::kFrameHeaderBytes, n);
        }
    }
    // The same bytes as a metadata block: whatever the client accepts, the server's encoder
    // writes back to a block of the same size that decodes to the same values.
    auto meta = navmap::ipc::decodeFrameMeta(data, size);
    if (meta.ok()) {
        const auto& m = meta.value();
        const auto bytes = navmap::ipc::encodeFrameMeta(m);
        auto again = navmap::ipc::decodeFrameMeta(bytes.data(), bytes.size());
        if (bytes.size() != size || !again.ok()) {
            __builtin_trap();
        }
        const auto& a = again.value();
        if (a.has_pose != m.has_pose || a.lat_deg != m.lat_deg || a.lon_deg != m.lon_deg ||
            a.heading_deg != m.heading_deg || a.pose_time_ns != m.pose_time_ns || a.has_next != m.has_next ||
            a.next_type != m.next_type || a.next_exit != m.next_exit || a.next_distance_m != m.next_distance_m ||
            a.next_street != m.next_street || a.lanes != m.lanes || a.has_remaining != m.has_remaining ||
            a.remaining_m != m.remaining_m || a.remaining_s != m.remaining_s || a.current_street != m.current_street ||
            a.speed_limit_kmh != m.speed_limit_kmh) {
            __builtin_trap();
        }
    }
    return 0;
}

#ifndef NAVMAP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    return navmapFuzzStreamHandshake(data, size);
}
#endif
