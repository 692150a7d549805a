// SPDX-License-Identifier: Apache-2.0
// Frame validity and the metadata block (docs/frame-protocol.md "Frame validity", "Metadata
// block"): the wire forms field by field, and every field through a real FrameServer to the C++
// client (shm, shm held in place, raw, zlib), to the C API, and to a client that did not ask.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_meta.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/client/zlib_inflater.h"
#include "navmap/ipc/stream/frame_server.h"
#include "navmap_client.h"
#include "stream_test_util.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

FrameMeta everyField() {
    FrameMeta m;
    m.has_pose = true;
    m.lat_deg = 42.50631;
    m.lon_deg = 1.52183;
    m.heading_deg = 271.25;
    m.pose_time_ns = 1764691200123456789LL;
    m.has_next = true;
    m.next_type = 12;  // roundabout
    m.next_exit = 3;
    m.next_distance_m = 187.5;
    m.next_street = "Avinguda de Tarragona";
    m.lanes_known = true;
    m.lanes = {kLaneLeft, kLaneStraight | kLaneRecommended, kLaneRight | kLaneSlightRight};
    m.has_remaining = true;
    m.remaining_m = 4213.25;
    m.remaining_s = 431.5;
    m.current_street = "Carrer Prat de la Creu";
    m.speed_limit_kmh = 50;
    return m;
}

void expectSame(const FrameMeta& a, const FrameMeta& b) {
    EXPECT_EQ(a.has_pose, b.has_pose);
    EXPECT_EQ(a.lat_deg, b.lat_deg);
    EXPECT_EQ(a.lon_deg, b.lon_deg);
    EXPECT_EQ(a.heading_deg, b.heading_deg);
    EXPECT_EQ(a.pose_time_ns, b.pose_time_ns);
    EXPECT_EQ(a.has_next, b.has_next);
    EXPECT_EQ(a.next_type, b.next_type);
    EXPECT_EQ(a.next_exit, b.next_exit);
    EXPECT_EQ(a.next_distance_m, b.next_distance_m);
    EXPECT_EQ(a.next_street, b.next_street);
    EXPECT_EQ(a.lanes_known, b.lanes_known);
    EXPECT_EQ(a.lanes, b.lanes);
    EXPECT_EQ(a.has_remaining, b.has_remaining);
    EXPECT_EQ(a.remaining_m, b.remaining_m);
    EXPECT_EQ(a.remaining_s, b.remaining_s);
    EXPECT_EQ(a.current_street, b.current_street);
    EXPECT_EQ(a.speed_limit_kmh, b.speed_limit_kmh);
}

FrameValidity staleOffRouteDegraded() {
    FrameValidity v;
    v.version = kFrameValidityVersion;
    v.flags = kValidityStalePose | kValidityDegraded | kValidityOffRoute;
    v.degraded = kDegradedTilesFailed | kDegradedOrthoimageOff;
    v.pose_age_ms = 2345;
    return v;
}

}  // namespace

TEST(FrameMetaWire, EveryFieldRoundTripsAtItsDocumentedOffset) {
    const FrameMeta m = everyField();
    const auto bytes = encodeFrameMeta(m);
    ASSERT_EQ(bytes.size(), kFrameMetaFixedBytes + 3 + m.next_street.size() + m.current_street.size());
    EXPECT_EQ(std::string(bytes.begin(), bytes.begin() + 4), "NMMD");
    EXPECT_EQ(bytes[4], 1);                                    // version
    EXPECT_EQ(bytes[6] | (bytes[7] << 8), int(bytes.size()));  // block bytes
    EXPECT_EQ(bytes[8], 0x0F);                                 // pose, next, remaining, lanes
    EXPECT_EQ(bytes[10], 12);
    EXPECT_EQ(bytes[11], 3);
    EXPECT_EQ(bytes[12], 50);
    EXPECT_EQ(bytes[14], m.next_street.size());
    EXPECT_EQ(bytes[15], m.current_street.size());
    EXPECT_EQ(bytes[72], 3);
    EXPECT_EQ(bytes[kFrameMetaFixedBytes + 1], kLaneStraight | kLaneRecommended);
    EXPECT_EQ(std::string(bytes.begin() + kFrameMetaFixedBytes + 3,
                          bytes.begin() + kFrameMetaFixedBytes + 3 + static_cast<long>(m.next_street.size())),
              m.next_street);
    auto d = decodeFrameMeta(bytes.data(), bytes.size());
    ASSERT_TRUE(d.ok()) << d.error().message;
    expectSame(d.value(), m);
    EXPECT_STREQ(metaManeuverName(d.value().next_type), "roundabout");
}

TEST(FrameMetaWire, UnknownsAreAbsentAndLongOrBrokenNamesAreBounded) {
    FrameMeta m;  // nothing known: no pose, no route, lanes and speed limit unknown
    m.current_street = std::string(300, 'a') + "\xC3\xA9";
    m.has_next = true;
    m.next_distance_m = std::nan("");  // not finite: sent as no next manoeuvre
    const auto bytes = encodeFrameMeta(m);
    auto d = decodeFrameMeta(bytes.data(), bytes.size());
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_FALSE(d.value().has_pose);
    EXPECT_FALSE(d.value().has_next);
    EXPECT_FALSE(d.value().has_remaining);
    EXPECT_FALSE(d.value().lanes_known);
    EXPECT_EQ(d.value().speed_limit_kmh, 0);
    EXPECT_EQ(d.value().current_street, std::string(255, 'a'));
    // Cut at a character boundary: "é" (2 bytes) does not fit after 254 bytes.
    EXPECT_EQ(boundedUtf8(std::string(254, 'b') + "\xC3\xA9", 255), std::string(254, 'b'));
    EXPECT_EQ(boundedUtf8("a\xFF"
                          "b",
                          255),
              "a?b");
}

TEST(FrameMetaWire, ValidityTravelsInTheFormerlyReservedHeaderBytes) {
    FrameHeader h;
    h.width = 64;
    h.height = 32;
    h.stride = 256;
    h.payload_bytes = 256 * 32;
    h.validity = staleOffRouteDegraded();
    h.meta_bytes = 120;
    const auto bytes = encodeFrameHeader(h);
    EXPECT_EQ(bytes[68], 1);
    EXPECT_EQ(bytes[69], 0x07);
    EXPECT_EQ(bytes[70], 0x0A);
    EXPECT_EQ(bytes[72] | (bytes[73] << 8), 2345);
    EXPECT_EQ(bytes[76], 120);
    auto d = decodeFrameHeader(bytes.data(), bytes.size());
    ASSERT_TRUE(d.ok()) << d.error().message;
    EXPECT_EQ(d.value().validity.flags, h.validity.flags);
    EXPECT_EQ(d.value().validity.degraded, h.validity.degraded);
    EXPECT_EQ(d.value().validity.pose_age_ms, 2345U);
    EXPECT_EQ(d.value().meta_bytes, 120);
    EXPECT_EQ(validityText(d.value().validity), "stale_pose+degraded+off_route");
    EXPECT_EQ(degradedText(d.value().validity.degraded), "tiles_failed+orthoimage_off");
    // A header of a server before validity existed: all zero, "unknown", still a frame.
    h.validity = {};
    h.meta_bytes = 0;
    const auto old = encodeFrameHeader(h);
    auto o = decodeFrameHeader(old.data(), old.size());
    ASSERT_TRUE(o.ok());
    EXPECT_EQ(validityText(o.value().validity), "unknown");
}

// Every field, from publish() through the server's sockets into each kind of client.
class FrameMetaStream : public ::testing::Test {
protected:
    void SetUp() override {
        FrameServerOptions o;
        o.unix_path = uniqueSocketPath("meta");
        o.tcp_port = 0;
        o.handshake_timeout = 3s;
        m_server = std::make_unique<FrameServer>(o);
        ASSERT_TRUE(m_server->start().ok());
    }
    StreamRequest request(StreamPayload payload, bool meta, bool hold = false) const {
        StreamRequest r;
        r.profile.name = "meta";
        r.profile.width = 64;
        r.profile.height = 32;
        r.profile.view = "bird";
        r.profile.fps = 0;
        r.payload = payload;
        r.meta = meta;
        r.hold = hold;
        return r;
    }
    std::unique_ptr<StreamClient> connect(const StreamRequest& r) {
        auto c = r.payload == StreamPayload::Shm
                     ? StreamClient::connectUnix(m_server->options().unix_path, r)
                     : StreamClient::connectTcp("127.0.0.1", m_server->tcpPort(), r, 5s, zlibInflater());
        EXPECT_TRUE(c.ok()) << (c.ok() ? "" : c.error().message);
        return c.ok() ? std::move(c.value()) : nullptr;
    }
    // Publishes until `got` says the client has a frame (the first publishes may precede its ring).
    template <typename Got>
    void publishUntil(Got got) {
        const auto px = sequencePattern(64, 32, 7);
        FrameView f;
        f.pixels = px.data();
        f.width = 64;
        f.height = 32;
        f.validity = staleOffRouteDegraded();
        f.meta = std::make_shared<const std::vector<std::uint8_t>>(encodeFrameMeta(everyField()));
        for (int i = 0; i < 100; ++i) {
            m_server->publish("bird", f);
            if (got()) return;
        }
        ADD_FAILURE() << "no frame";
    }
    std::unique_ptr<FrameServer> m_server;
};

TEST_F(FrameMetaStream, EveryFieldReachesTheCppClientOnEveryPayload) {
    for (const auto payload : {StreamPayload::Shm, StreamPayload::Raw, StreamPayload::Zlib}) {
        SCOPED_TRACE(streamPayloadName(payload));
        auto c = connect(request(payload, true));
        ASSERT_NE(c, nullptr);
        ReceivedFrame f;
        publishUntil([&] {
            auto r = c->next(f, 100ms);
            EXPECT_TRUE(r.ok()) << r.error().message;
            return r.ok() && r.value();
        });
        ASSERT_TRUE(f.meta.has_value());
        expectSame(*f.meta, everyField());
        EXPECT_EQ(f.header.validity.flags, staleOffRouteDegraded().flags);
        EXPECT_EQ(f.header.validity.degraded, staleOffRouteDegraded().degraded);
        EXPECT_EQ(f.header.validity.pose_age_ms, 2345U);
    }
}

TEST_F(FrameMetaStream, AHeldFrameCarriesItsBlockAndAClientThatDidNotAskGetsNone) {
    auto held = connect(request(StreamPayload::Shm, true, true));
    auto plain = connect(request(StreamPayload::Raw, false));
    ASSERT_NE(held, nullptr);
    ASSERT_NE(plain, nullptr);
    HeldFrame h;
    ReceivedFrame p;
    bool got_held = false;
    bool got_plain = false;
    publishUntil([&] {
        if (!got_held) got_held = held->nextHeld(h, 50ms).value();
        if (!got_plain) got_plain = plain->next(p, 50ms).value();
        return got_held && got_plain;
    });
    ASSERT_TRUE(h.meta.has_value());
    expectSame(*h.meta, everyField());
    EXPECT_TRUE(held->release().value());
    // The old-style client: no block on its socket, the validity in its header all the same.
    EXPECT_FALSE(p.meta.has_value());
    EXPECT_EQ(p.header.meta_bytes, 0);
    EXPECT_EQ(p.header.validity.flags, staleOffRouteDegraded().flags);
}

TEST_F(FrameMetaStream, TheCApiHandsOutEveryField) {
    navmap_client_options o;
    navmap_client_options_init(&o);
    const std::string path = m_server->options().unix_path;
    o.socket_path = path.c_str();
    o.profile = "meta";
    o.width = 64;
    o.height = 32;
    o.view = "bird";
    navmap_client* c = navmap_client_create(&o, nullptr);
    ASSERT_NE(c, nullptr);
    ASSERT_EQ(navmap_client_request_meta(c, 1), 0);
    navmap_frame f;
    publishUntil([&] { return navmap_client_next_frame(c, 50, &f) == NAVMAP_CLIENT_FRAME; });
    EXPECT_EQ(navmap_client_request_meta(c, 0), NAVMAP_CLIENT_ERROR);  // connected: too late
    navmap_frame_validity v;
    ASSERT_EQ(navmap_client_frame_validity(c, &f, &v), NAVMAP_CLIENT_FRAME);
    EXPECT_EQ(v.known, 1);
    EXPECT_EQ(v.flags, unsigned(NAVMAP_VALID_STALE_POSE | NAVMAP_VALID_DEGRADED | NAVMAP_VALID_OFF_ROUTE));
    EXPECT_EQ(v.degraded, unsigned(NAVMAP_DEGRADED_TILES_FAILED | NAVMAP_DEGRADED_ORTHOIMAGE_OFF));
    EXPECT_EQ(v.pose_age_ms, 2345U);
    navmap_frame_meta m;
    ASSERT_EQ(navmap_client_frame_meta(c, &f, &m), NAVMAP_CLIENT_FRAME);
    const FrameMeta want = everyField();
    EXPECT_EQ(m.has_pose, 1);
    EXPECT_EQ(m.lat_deg, want.lat_deg);
    EXPECT_EQ(m.lon_deg, want.lon_deg);
    EXPECT_EQ(m.heading_deg, want.heading_deg);
    EXPECT_EQ(m.pose_time_ns, want.pose_time_ns);
    EXPECT_EQ(m.has_next, 1);
    EXPECT_STREQ(m.next_type, "roundabout");
    EXPECT_EQ(m.next_exit, 3);
    EXPECT_EQ(m.next_distance_m, want.next_distance_m);
    EXPECT_STREQ(m.next_street, "Avinguda de Tarragona");
    ASSERT_EQ(m.lane_count, 3);
    EXPECT_EQ(m.lanes[1], kLaneStraight | kLaneRecommended);
    EXPECT_EQ(m.has_remaining, 1);
    EXPECT_EQ(m.remaining_m, want.remaining_m);
    EXPECT_EQ(m.remaining_s, want.remaining_s);
    EXPECT_STREQ(m.current_street, "Carrer Prat de la Creu");
    EXPECT_EQ(m.speed_limit_kmh, 50);
    navmap_frame other = f;
    other.sequence += 1;
    EXPECT_EQ(navmap_client_frame_meta(c, &other, &m), NAVMAP_CLIENT_ERROR);  // not the frame held
    EXPECT_EQ(navmap_client_release_frame(c, &f), NAVMAP_CLIENT_FRAME);
    EXPECT_EQ(navmap_client_frame_validity(c, &f, &v), NAVMAP_CLIENT_ERROR);  // released
    navmap_client_destroy(c);
}
