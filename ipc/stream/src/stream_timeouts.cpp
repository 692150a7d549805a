// SPDX-License-Identifier: Apache-2.0
#include "stream_timeouts.h"

#include <linux/sockios.h>
#include <sys/ioctl.h>

#include <algorithm>
#include <cstdint>
#include <utility>

#include "stream_rings.h"

namespace navmap::ipc::stream_detail {

int StreamTimeouts::trackProgress(StreamConn& c, Clock::time_point now) {
    // TCP: a send() only proves the kernel had room (hundreds of kB); progress is the peer
    // taking bytes out of the send queue (SIOCOUTQ = bytes not yet acknowledged).
    int outq = 0;
    if (c.via != Via::Unix && ::ioctl(c.fd.get(), SIOCOUTQ, &outq) == 0) {
        const std::uint64_t acked =
            c.bytes_sent - std::min<std::uint64_t>(c.bytes_sent, static_cast<std::uint64_t>(outq));
        if (acked > c.bytes_acked || (outq == 0 && !c.outPending())) {
            c.bytes_acked = acked;
            c.last_progress = now;
        }
    }
    return outq;
}

std::string StreamTimeouts::within() const {
    return " within " + std::to_string(m_options.handshake_timeout.count()) + " ms";
}

std::string StreamTimeouts::firstFrameWhy(const StreamConn& c) const {
    const FrameRingLayout& l = c.ring->ring->layout();
    return "no frame" + within() + " of the handshake (nothing published for " + c.ring->view + " " +
           std::to_string(l.width) + "x" + std::to_string(l.height) + ")";
}

std::string StreamTimeouts::stallWhy(const StreamConn& c, int outq, Clock::time_point now) const {
    const auto limit = m_options.stall_timeout;
    std::string why;
    if (c.phase == Phase::Draining && now - c.since > limit) {
        why = "did not close";
    } else if (c.awaiting_ack && now - c.ack_since > limit) {
        why = "no ack";
    } else if ((c.outPending() || outq > 0) && now - c.last_progress > limit) {
        why = "not reading";
    }
    return why.empty() ? why : why + " for " + std::to_string(limit.count()) + " ms";
}

TimeoutVerdict StreamTimeouts::check(StreamConn& c, Clock::time_point now) const {
    const int outq = trackProgress(c, now);
    const auto earn = m_options.handshake_timeout;
    if ((c.phase == Phase::Handshake || c.phase == Phase::HttpHead) && now - c.since > earn) {
        return {TimeoutVerdict::Kind::Handshake,
                (c.phase == Phase::HttpHead ? "no complete request head" : "no complete handshake") + within()};
    }
    if ((c.phase == Phase::Stream || c.phase == Phase::Mjpeg) && c.last_sent == 0 && now - c.stream_since > earn) {
        return {TimeoutVerdict::Kind::FirstFrame, firstFrameWhy(c)};
    }
    std::string why = stallWhy(c, outq, now);
    if (why.empty()) {
        return {};
    }
    return {TimeoutVerdict::Kind::Stall, std::move(why)};
}

}  // namespace navmap::ipc::stream_detail
