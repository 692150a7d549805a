// SPDX-License-Identifier: Apache-2.0
#include "frame_stream_transport.h"

#include <algorithm>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "stream_rings.h"

namespace navmap::ipc::stream_detail {

std::string errorFrame(const std::string& text) {
    FrameHeader h;
    h.kind = FrameKind::Error;
    h.payload_bytes = static_cast<std::uint32_t>(text.size());
    const auto hb = encodeFrameHeader(h);
    return std::string(hb.begin(), hb.end()) + text;
}

void FrameStreamTransport::onInput(StreamConn& c) {
    switch (c.phase) {
        case Phase::Handshake: onHandshakeBytes(c); return;
        case Phase::Stream: onStreamBytes(c); return;
        default: c.in.clear(); return;
    }
}

void FrameStreamTransport::onHandshakeBytes(StreamConn& c) {
    if (hasControlBytes(c.in)) {
        handshakeError(c, "handshake: binary data (expected one JSON line)");
        return;
    }
    const auto nl = c.in.find('\n');
    if (nl == std::string::npos) {
        if (c.in.size() > kMaxHandshakeBytes) {
            handshakeError(c, "handshake: longer than " + std::to_string(kMaxHandshakeBytes) + " bytes");
        }
        return;
    }
    const std::string line = c.in.substr(0, nl + 1);
    c.in.erase(0, nl + 1);
    onHandshake(c, line);
    if (!c.dead && c.phase == Phase::Stream && !c.in.empty()) {
        onStreamBytes(c);
    }
}

void FrameStreamTransport::onHandshake(StreamConn& c, const std::string& line) {
    auto req = parseStreamRequest(line);
    if (!req) {
        handshakeError(c, req.error().message);
        return;
    }
    const StreamRequest& r = req.value();
    if (r.payload == StreamPayload::Shm && !carriesShm()) {
        handshakeError(c, "handshake: payload \"shm\" needs the Unix socket; use \"raw\" or \"zlib\" over TCP");
        return;
    }
    if (r.payload == StreamPayload::Dmabuf) {
        if (!carriesShm()) {
            handshakeError(c, "handshake: payload \"dmabuf\" needs the Unix socket; use \"raw\" or \"zlib\" over TCP");
            return;
        }
        const auto& available = m_hub.options().dmabuf_unavailable_reason;
        const std::string why = available ? available() : std::string("this server exports no dma-buf frames");
        if (!why.empty()) {
            handshakeError(c, "handshake: dmabuf frames are not available here (" + why + "); ask for shm");
            return;
        }
        if (r.profile.format != PixelFormat::Rgba8) {
            handshakeError(c, "handshake: dmabuf frames are rgba8 (DRM_FORMAT_ABGR8888); ask for format rgba8");
            return;
        }
    }
    auto key = m_hub.rings().resolve(r.profile);
    if (!key) {
        handshakeError(c, "handshake: " + key.error().message);
        return;
    }
    auto ring = m_hub.rings().attach(key.value(), r.profile);
    if (!ring) {
        handshakeError(c, ring.error().message);
        return;
    }
    c.ring = ring.value();
    if (r.payload == StreamPayload::Dmabuf) {
        ++c.ring->dmabuf_clients;
    }
    c.payload = r.payload;
    c.hold = r.hold;
    c.meta = r.meta;
    c.fps = r.profile.fps;
    c.ring->max_fps = std::max(c.ring->max_fps, effectiveFps(c.fps));
    if (!sendReply(c, handshakeReply(c, r))) {
        return;
    }
    c.phase = Phase::Stream;
    c.last_progress = c.stream_since = Clock::now();
    m_hub.refreshRings();
    m_hub.offerIfNew(c, Clock::now());
}

std::string FrameStreamTransport::handshakeReply(const StreamConn& c, const StreamRequest& r) const {
    const FrameRingLayout& l = c.ring->ring->layout();
    nlohmann::json reply;
    reply["ok"] = true;
    reply["version"] = 1;
    reply["profile"] = {{"name", r.profile.name},     {"width", r.profile.width},
                        {"height", r.profile.height}, {"fps", r.profile.fps},
                        {"view", r.profile.view},     {"format", pixelFormatName(r.profile.format)}};
    reply["payload"] = streamPayloadName(r.payload);
    if (r.hold) {
        reply["hold"] = true;
    }
    if (r.meta) {
        reply["meta"] = kFrameMetaVersion;  // the block version every frame header's block has
    }
    reply["stride"] = l.stride;
    reply["header_bytes"] = kFrameHeaderBytes;
    if (r.payload == StreamPayload::Dmabuf) {
        reply["dmabuf"] = kDmabufBlockVersion;  // the block layout every dma-buf frame has
    }
    if (r.payload == StreamPayload::Shm) {
        reply["ring"] = {{"slots", l.slots},
                         {"slot_bytes", l.slot_bytes},
                         {"total_bytes", l.total_bytes},
                         {"header_offset", kSlotHeaderOffset},
                         {"pixel_offset", kSlotPixelOffset}};
    }
    return reply.dump() + "\n";
}

bool FrameStreamTransport::sendReply(StreamConn& c, const std::string& text) {
    c.queue(text.data(), text.size());
    return true;
}

bool FrameStreamTransport::takeAck(StreamConn&, unsigned char) { return false; }

void FrameStreamTransport::onStreamBytes(StreamConn& c) {
    // After the handshake a shm client sends one 'A' per frame it has copied (its credit back);
    // socket-payload clients send nothing.
    for (const char ch : c.in) {
        const auto b = static_cast<unsigned char>(ch);
        if (takeAck(c, b)) {
            continue;
        }
        char msg[96];
        std::snprintf(msg, sizeof(msg), "unexpected byte 0x%02x after the handshake%s", b,
                      c.payload == StreamPayload::Shm && b == 'A' ? " (ack without a frame)" : "");
        protocolError(c, msg);
        return;
    }
    c.in.clear();
}

void FrameStreamTransport::handshakeError(StreamConn& c, const std::string& message) {
    m_hub.stats().countError(&FrameServerStats::handshake_errors, c.peer + ": " + message);
    m_hub.finishWith(c, jsonErrorLine(message));
}

void FrameStreamTransport::protocolError(StreamConn& c, const std::string& message) {
    m_hub.stats().countError(&FrameServerStats::protocol_errors, c.peer + ": " + message);
    // The error travels as a header of kind Error after whatever frame is in flight.
    c.in.clear();
    c.pending = false;
    c.awaiting_ack = false;
    c.unpin();
    m_hub.finishWith(c, errorFrame(message));
}

std::string FrameStreamTransport::firstFrameTimeoutReply(const StreamConn& c, const std::string& text) const {
    // The server's last word, as a header of kind Error (docs/frame-protocol.md).
    return c.outPending() ? std::string() : errorFrame(text);
}

bool FrameStreamTransport::readFrame(StreamConn& c, std::uint64_t seq, FrameHeader* h) {
    const bool ok = c.ring->fillRaw(seq);
    *h = c.ring->raw_header;
    return ok;
}

FrameStreamTransport::ReadOutcome FrameStreamTransport::readNewest(StreamConn& c, std::uint64_t* seq, FrameHeader* h) {
    // The newest frame; if the render thread overwrites it meanwhile, take the one after.
    for (int attempt = 0; attempt < 4; ++attempt) {
        *seq = c.ring->ring->latestSequence();
        if (*seq == 0 || *seq <= c.last_sent || *seq < c.ring->first_seq) {
            return ReadOutcome::Nothing;
        }
        if (readFrame(c, *seq, h)) {
            return ReadOutcome::Ready;
        }
    }
    return ReadOutcome::Retry;
}

void FrameStreamTransport::sendFrame(StreamConn& c) {
    c.pending = false;
    std::uint64_t seq = 0;
    FrameHeader h;
    std::shared_ptr<const EncodedFrame> encoded;
    if (c.payload == StreamPayload::Zlib) {
        // Encoded by the encoder thread; the newest finished one.
        encoded = c.ring->zlib;
        if (!encoded || encoded->sequence <= c.last_sent) {
            return;
        }
        seq = encoded->sequence;
        h = encoded->header;
    } else if (const auto got = readNewest(c, &seq, &h); got != ReadOutcome::Ready) {
        c.pending = got == ReadOutcome::Retry;  // overwritten each time: try again on the next wake-up
        return;
    }
    h.dropped = c.dropped;
    queueFrame(c, h, encoded.get());
    m_hub.frameSent(c, seq);
}

void FrameStreamTransport::queueFrame(StreamConn& c, FrameHeader h, const EncodedFrame* encoded) {
    const bool zlib = encoded != nullptr;
    h.encoding = zlib ? FrameEncoding::Zlib : FrameEncoding::Raw;
    const auto& payload = zlib ? encoded->bytes : c.ring->raw;
    h.payload_bytes = static_cast<std::uint32_t>(payload.size());
    queueHeader(c, h);
    c.queue(payload.data(), payload.size());
}

void FrameStreamTransport::queueHeader(StreamConn& c, FrameHeader h) {
    // The frame's metadata block follows its header, for the clients that asked for it; a frame
    // published without one (or one too old to be kept) goes without.
    const auto block = c.meta ? c.ring->meta->get(h.sequence) : FrameMetaHistory::Block{};
    h.meta_bytes = block ? static_cast<std::uint16_t>(block->size()) : 0;
    const auto hb = encodeFrameHeader(h);
    c.queue(hb.data(), hb.size());
    if (block) {
        c.queue(block->data(), block->size());
    }
}

}  // namespace navmap::ipc::stream_detail
