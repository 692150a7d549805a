// SPDX-License-Identifier: Apache-2.0
// The C API of libnavmap-client (navmap_client.h) over ReconnectingClient.

#include "navmap_client.h"

#include <exception>
#include <memory>
#include <new>
#include <string>

#include "navmap/ipc/client/reconnecting_client.h"

struct navmap_client {
    std::unique_ptr<navmap::ipc::ReconnectingClient> client;
    navmap::ipc::HeldFrame held;
    bool holding = false;
    std::uint64_t frames = 0;
    mutable std::string error;     // navmap_client_last_error()'s storage
    mutable std::string fallback;  // navmap_client_payload_fallback()'s storage
};

namespace {

std::chrono::milliseconds orDefault(int ms, int fallback) { return std::chrono::milliseconds(ms > 0 ? ms : fallback); }

// `frame` is the one navmap_client_next_frame() handed out and not released yet.
bool heldFrame(const navmap_client* client, const navmap_frame* frame) {
    return frame != nullptr && client->holding && frame->sequence == client->held.header.sequence &&
           frame->pixels == client->held.pixels;
}

}  // namespace

extern "C" {
// The C API keeps its C names (navmap_client.h).
// NOLINTBEGIN(readability-identifier-naming)

const char* navmap_client_version(void) { return NAVMAP_VERSION; }

void navmap_client_options_init(navmap_client_options* options) {
    if (options != nullptr) {
        *options = navmap_client_options{};
        options->format = NAVMAP_FORMAT_RGBA8;
    }
}

navmap_client* navmap_client_create(const navmap_client_options* options, const char** error) {
    const auto fail = [error](const char* why) -> navmap_client* {
        if (error != nullptr) {
            *error = why;
        }
        return nullptr;
    };
    if (options == nullptr || options->socket_path == nullptr || options->socket_path[0] == '\0') {
        return fail("navmap_client_create: socket_path is required");
    }
    if (options->profile == nullptr || options->profile[0] == '\0') {
        return fail("navmap_client_create: profile is required");
    }
    navmap::ipc::ReconnectOptions o;
    o.unix_path = options->socket_path;
    auto& p = o.request.profile;
    if (auto d = navmap::ipc::defaultStreamProfile(options->profile)) {
        p = *d;
    } else {
        p.name = options->profile;
        if (options->width <= 0 || options->height <= 0 || options->view == nullptr) {
            return fail("navmap_client_create: a profile other than cluster, hud, center needs width, height and view");
        }
    }
    if (options->width != 0 || options->height != 0) {
        if (options->width < navmap::ipc::kMinStreamDimension || options->width > navmap::ipc::kMaxStreamDimension ||
            options->height < navmap::ipc::kMinStreamDimension || options->height > navmap::ipc::kMaxStreamDimension) {
            return fail("navmap_client_create: width and height must be in [16, 4096]");
        }
        p.width = options->width;
        p.height = options->height;
    }
    if (options->view != nullptr) {
        const std::string v = options->view;
        if (v != "bird" && v != "snail" && v != "hud") {
            return fail("navmap_client_create: view must be bird, snail or hud");
        }
        p.view = v;
    }
    if (options->fps < 0 || options->fps > navmap::ipc::kMaxStreamFps) {
        return fail("navmap_client_create: fps must be in [0, 1000] (0: the profile's)");
    }
    if (options->fps > 0) {
        p.fps = options->fps;
    }
    if (options->format == NAVMAP_FORMAT_RGB565) {
        p.format = navmap::ipc::PixelFormat::Rgb565;
    } else if (options->format == NAVMAP_FORMAT_RGBA8 || options->format == 0) {
        p.format = navmap::ipc::PixelFormat::Rgba8;
    } else {
        return fail("navmap_client_create: format must be NAVMAP_FORMAT_RGBA8 or NAVMAP_FORMAT_RGB565");
    }
    if (options->connect_timeout_ms < 0 || options->reconnect_initial_ms < 0 || options->reconnect_max_ms < 0) {
        return fail("navmap_client_create: timeouts must not be negative");
    }
    o.request.payload = navmap::ipc::StreamPayload::Shm;
    o.request.hold = true;  // frames are handed out in place until navmap_client_release_frame()
    o.connect_timeout = orDefault(options->connect_timeout_ms, 2000);
    o.initial_backoff = orDefault(options->reconnect_initial_ms, 100);
    o.max_backoff = orDefault(options->reconnect_max_ms, 5000);
    auto* c = new (std::nothrow) navmap_client;
    if (c == nullptr) {
        return fail("navmap_client_create: out of memory");
    }
    try {
        c->client = std::make_unique<navmap::ipc::ReconnectingClient>(std::move(o));
    } catch (const std::exception&) {
        delete c;
        return fail("navmap_client_create: out of memory");
    }
    return c;
}

int navmap_client_next_frame(navmap_client* client, int timeout_ms, navmap_frame* frame) {
    if (client == nullptr || frame == nullptr || timeout_ms < 0) {
        return NAVMAP_CLIENT_ERROR;
    }
    try {
        client->holding = false;  // nextHeld() releases the frame still held
        if (!client->client->nextHeld(client->held, std::chrono::milliseconds(timeout_ms))) {
            return client->client->connected() ? NAVMAP_CLIENT_TIMEOUT : NAVMAP_CLIENT_DISCONNECTED;
        }
    } catch (const std::exception& e) {
        // Only allocation can throw here; the C caller gets a status, never an exception.
        client->error = e.what();
        return NAVMAP_CLIENT_DISCONNECTED;
    }
    const auto& h = client->held.header;
    frame->pixels = client->held.pixels;
    frame->width = h.width;
    frame->height = h.height;
    frame->stride = h.stride;
    frame->format = static_cast<int>(h.format);
    frame->sequence = h.sequence;
    frame->render_time_ns = h.render_time_ns;
    frame->source_time_ns = h.source_time_ns;
    frame->receive_time_ns = client->held.receive_time_ns;
    frame->dropped = h.dropped;
    client->holding = true;
    ++client->frames;
    return NAVMAP_CLIENT_FRAME;
}

int navmap_client_release_frame(navmap_client* client, const navmap_frame* frame) {
    if (client == nullptr || frame == nullptr || !client->holding || frame->sequence != client->held.header.sequence ||
        frame->pixels != client->held.pixels) {
        return NAVMAP_CLIENT_ERROR;
    }
    client->holding = false;
    return client->client->release() ? NAVMAP_CLIENT_FRAME : NAVMAP_CLIENT_OVERWRITTEN;
}

int navmap_client_request_meta(navmap_client* client, int on) {
    if (client == nullptr || client->client->connected()) {
        return NAVMAP_CLIENT_ERROR;
    }
    client->client->requestMeta(on != 0);
    return 0;
}

int navmap_client_request_dmabuf(navmap_client* client) {
    if (client == nullptr || client->client->connected()) {
        return NAVMAP_CLIENT_ERROR;
    }
    client->client->requestDmabuf(true);  // a navmapd that cannot export: shm frames as always
    return 0;
}

int navmap_client_frame_dmabuf(const navmap_client* client, const navmap_frame* frame, navmap_dmabuf* dmabuf) {
    if (client == nullptr || dmabuf == nullptr || !heldFrame(client, frame) || client->held.dmabuf_fd < 0) {
        return NAVMAP_CLIENT_ERROR;
    }
    const auto& b = client->held.dmabuf;
    dmabuf->fd = client->held.dmabuf_fd;
    dmabuf->fourcc = b.fourcc;
    dmabuf->modifier = b.modifier;
    dmabuf->offset = b.offset;
    dmabuf->stride = b.stride;
    dmabuf->buffer = client->held.header.slot;
    dmabuf->new_buffer = (b.flags & navmap::ipc::kDmabufBufferFd) != 0 ? 1 : 0;
    return NAVMAP_CLIENT_FRAME;
}

const char* navmap_client_payload(const navmap_client* client) {
    if (client == nullptr || client->client->client() == nullptr) {
        return "";
    }
    return navmap::ipc::streamPayloadName(client->client->client()->payload());
}

const char* navmap_client_payload_fallback(const navmap_client* client) {
    if (client == nullptr || client->client->client() == nullptr) {
        return "";
    }
    client->fallback = client->client->client()->fallbackReason();
    return client->fallback.c_str();
}

int navmap_client_frame_validity(const navmap_client* client, const navmap_frame* frame,
                                 navmap_frame_validity* validity) {
    if (client == nullptr || validity == nullptr || !heldFrame(client, frame)) {
        return NAVMAP_CLIENT_ERROR;
    }
    const auto& v = client->held.header.validity;
    validity->known = v.known() ? 1 : 0;
    validity->flags = v.flags;
    validity->degraded = v.degraded;
    validity->pose_age_ms = v.pose_age_ms;
    return NAVMAP_CLIENT_FRAME;
}

int navmap_client_frame_meta(const navmap_client* client, const navmap_frame* frame, navmap_frame_meta* meta) {
    if (client == nullptr || meta == nullptr || !heldFrame(client, frame)) {
        return NAVMAP_CLIENT_ERROR;
    }
    *meta = navmap_frame_meta{};
    if (!client->held.meta) {
        return NAVMAP_CLIENT_TIMEOUT;
    }
    const auto& m = *client->held.meta;
    meta->has_pose = m.has_pose ? 1 : 0;
    meta->lat_deg = m.lat_deg;
    meta->lon_deg = m.lon_deg;
    meta->heading_deg = m.heading_deg;
    meta->pose_time_ns = m.pose_time_ns;
    meta->has_next = m.has_next ? 1 : 0;
    const char* type = m.has_next ? navmap::ipc::metaManeuverName(m.next_type) : nullptr;
    meta->next_type = type != nullptr ? type : "";
    meta->next_exit = m.next_exit;
    meta->next_distance_m = m.next_distance_m;
    meta->next_street = m.next_street.c_str();
    meta->lane_count = m.lanes_known ? static_cast<int>(m.lanes.size()) : -1;
    for (std::size_t i = 0; i < m.lanes.size() && i < sizeof(meta->lanes); ++i) {
        meta->lanes[i] = m.lanes[i];
    }
    meta->has_remaining = m.has_remaining ? 1 : 0;
    meta->remaining_m = m.remaining_m;
    meta->remaining_s = m.remaining_s;
    meta->current_street = m.current_street.c_str();
    meta->speed_limit_kmh = m.speed_limit_kmh;
    return NAVMAP_CLIENT_FRAME;
}

int navmap_client_connected(const navmap_client* client) {
    return client != nullptr && client->client->connected() ? 1 : 0;
}

const char* navmap_client_last_error(const navmap_client* client) {
    if (client == nullptr) {
        return "navmap_client_last_error: no client";
    }
    if (!client->client->lastError().empty()) {
        client->error = client->client->lastError();
    }
    return client->error.c_str();
}

void navmap_client_get_stats(const navmap_client* client, navmap_client_stats* stats) {
    if (client == nullptr || stats == nullptr) {
        return;
    }
    const auto& r = client->client->reconnectStats();
    stats->frames = client->frames;
    stats->connects = r.connects;
    stats->failed_attempts = r.failed_attempts;
    stats->disconnects = r.disconnects;
    stats->held_overwritten = r.held_overwritten;
}

void navmap_client_destroy(navmap_client* client) { delete client; }
// NOLINTEND(readability-identifier-naming)

}  // extern "C"
