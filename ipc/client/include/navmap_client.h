// SPDX-License-Identifier: Apache-2.0
/* navmap_client.h: the C API of libnavmap-client, for display processes whose HMI stack is not
 * C++ (docs/frame-protocol.md "Client library"). A client connects to navmapd's frame socket with
 * a display profile, reconnects by itself with exponential backoff whenever navmapd is not there,
 * and hands out frames without copying them: a frame's pixels stay in the shared-memory ring
 * that the client maps read-only, valid until navmap_client_release_frame().
 *
 *   navmap_client_options o;
 *   navmap_client_options_init(&o);
 *   o.socket_path = "/run/navmap/frames.sock";
 *   o.profile = "cluster";
 *   navmap_client* c = navmap_client_create(&o);
 *   navmap_frame f;
 *   for (;;) {
 *       int r = navmap_client_next_frame(c, 200, &f);
 *       if (r == NAVMAP_CLIENT_FRAME) { show(f.pixels, f.width, f.height, f.stride); navmap_client_release_frame(c,
 * &f); } else if (r == NAVMAP_CLIENT_ERROR) break;                   // bad arguments
 *       // NAVMAP_CLIENT_TIMEOUT, NAVMAP_CLIENT_DISCONNECTED: navmap_client_last_error(c) says why
 *   }
 *   navmap_client_destroy(c);
 *
 * Links only the C and C++ runtime (no zlib, no JPEG, no server code). Not thread-safe: one
 * thread owns a client; several clients in one process are independent. */
#ifndef NAVMAP_CLIENT_H
#define NAVMAP_CLIENT_H

#include <stdint.h>

#include "navmap/version.h"

#ifdef __cplusplus
extern "C" {
#endif

/* A C API: C names (snake_case types and functions, upper-case constants), not the C++ code's
 * naming rules (CONTRIBUTING.md "Lint"). */
/* NOLINTBEGIN(readability-identifier-naming) */

#define NAVMAP_CLIENT_EXPORT __attribute__((visibility("default")))

/* Results of navmap_client_next_frame() and navmap_client_release_frame(). */
enum {
    NAVMAP_CLIENT_FRAME = 1,         /* a frame was handed out / released intact */
    NAVMAP_CLIENT_TIMEOUT = 0,       /* connected, no new frame within the timeout */
    NAVMAP_CLIENT_DISCONNECTED = -1, /* not connected (navmapd gone, refused, restarting); retrying */
    NAVMAP_CLIENT_OVERWRITTEN = -2,  /* release: the server had to overwrite the held frame */
    NAVMAP_CLIENT_ERROR = -3         /* bad arguments (a null pointer, a frame not held) */
};

/* Pixel formats (docs/frame-protocol.md): RGBA8 is R,G,B,A bytes; RGB565 a little-endian
 * 16-bit word r<<11 | g<<5 | b. Rows top to bottom. */
enum { NAVMAP_FORMAT_RGBA8 = 1, NAVMAP_FORMAT_RGB565 = 2 };

typedef struct navmap_client_options {
    const char* socket_path;  /* navmapd's frame socket, e.g. "/run/navmap/frames.sock" (required) */
    const char* profile;      /* "cluster", "hud", "center" or a profile navmapd renders (required) */
    int width, height;        /* 0: the named default profile's size */
    const char* view;         /* "snail", "bird", "hud"; NULL: the named default profile's */
    int fps;                  /* most frames per second wanted, 1..1000; 0: the profile's (30) */
    int format;               /* NAVMAP_FORMAT_RGBA8 (default) or NAVMAP_FORMAT_RGB565 */
    int connect_timeout_ms;   /* connect + handshake per attempt; 0: 2000 */
    int reconnect_initial_ms; /* first wait after a failure, doubling; 0: 100 */
    int reconnect_max_ms;     /* longest wait between attempts; 0: 5000 */
} navmap_client_options;

typedef struct navmap_frame {
    const uint8_t* pixels; /* in the read-only mapped ring; valid until released */
    uint32_t width, height;
    uint32_t stride;         /* bytes per row */
    int format;              /* NAVMAP_FORMAT_* */
    uint64_t sequence;       /* per profile, +1 per rendered frame */
    int64_t render_time_ns;  /* CLOCK_REALTIME ns the frame was published */
    int64_t source_time_ns;  /* CLOCK_REALTIME ns the CAN data behind the pose arrived; 0: none */
    int64_t receive_time_ns; /* CLOCK_REALTIME ns this client got the notification */
    uint64_t dropped;        /* frames this connection missed so far */
} navmap_frame;

/* Frame validity (docs/frame-protocol.md "Frame validity"): every frame says whether it can be
 * trusted. Flags (none set: fresh): */
enum {
    NAVMAP_VALID_STALE_POSE = 1, /* no pose for more than navmapd's stale_pose_ms (or none yet) */
    NAVMAP_VALID_DEGRADED = 2,   /* something under the camera is missing: see `degraded` */
    NAVMAP_VALID_OFF_ROUTE = 4   /* guidance says the vehicle left its route */
};
/* Why a frame is degraded. */
enum {
    NAVMAP_DEGRADED_TILES_MISSING = 1,  /* tiles wanted under the camera are not loaded yet */
    NAVMAP_DEGRADED_TILES_FAILED = 2,   /* tiles under the camera failed to load (damaged) */
    NAVMAP_DEGRADED_ROAD_GRAPH_OFF = 4, /* no road graph: no map matching */
    NAVMAP_DEGRADED_ORTHOIMAGE_OFF = 8  /* the orthoimage ground is asked for and not drawn */
};
#define NAVMAP_POSE_AGE_NONE 0xFFFFFFFFu /* pose_age_ms when there has been no pose */

typedef struct navmap_frame_validity {
    int known;            /* 0: the server reports no validity (a navmapd before it); the rest is 0 */
    unsigned flags;       /* NAVMAP_VALID_*; 0 = fresh */
    unsigned degraded;    /* NAVMAP_DEGRADED_*, non-zero exactly with NAVMAP_VALID_DEGRADED */
    uint32_t pose_age_ms; /* ms from the newest pose fix to the render; NAVMAP_POSE_AGE_NONE: none yet */
} navmap_frame_validity;

/* A frame's guidance metadata (docs/frame-protocol.md "Metadata block"), for a client that asked
 * for it with navmap_client_request_meta(). Strings are UTF-8 (at most 255 bytes), "" when
 * unknown, and like the pixels valid until the frame is released. */
typedef struct navmap_frame_meta {
    int has_pose; /* 0: no fix yet (the pose fields are 0) */
    double lat_deg, lon_deg;
    double heading_deg;     /* clockwise from north, [0, 360) */
    int64_t pose_time_ns;   /* CLOCK_REALTIME ns of the CAN data behind the pose */
    int has_next;           /* 0: no next manoeuvre (no route, arrived) */
    const char* next_type;  /* "turn_left", "roundabout", ... (docs/ipc.md); "" without one */
    int next_exit;          /* roundabout exit, 1..; 0 none */
    double next_distance_m; /* along the route to its junction */
    const char* next_street;
    int lane_count;    /* -1: unknown (no lane data); else lanes[0..lane_count) left to right */
    uint8_t lanes[16]; /* bits 0..5: left, slight left, straight, slight right, right, u-turn; bit 7: take it */
    int has_remaining; /* 0: no route followed */
    double remaining_m, remaining_s;
    const char* current_street; /* the map-matched road's name */
    int speed_limit_kmh;        /* 0: unknown */
} navmap_frame_meta;

typedef struct navmap_client_stats {
    uint64_t frames;           /* frames handed out */
    uint64_t connects;         /* successful connections (the first included) */
    uint64_t failed_attempts;  /* connection attempts that failed */
    uint64_t disconnects;      /* streams that ended */
    uint64_t held_overwritten; /* held frames the server overwrote before their release */
} navmap_client_stats;

typedef struct navmap_client navmap_client;

/* The library's version, "MAJOR.MINOR.PATCH" (NAVMAP_VERSION is the headers'). */
NAVMAP_CLIENT_EXPORT const char* navmap_client_version(void);

/* Fills *options with the defaults (all zero/NULL: cluster profile values come from `profile`). */
NAVMAP_CLIENT_EXPORT void navmap_client_options_init(navmap_client_options* options);

/* Creates a client; it connects on the first navmap_client_next_frame(). NULL when the options
 * are invalid; *error (if not NULL) then points to a static message. */
NAVMAP_CLIENT_EXPORT navmap_client* navmap_client_create(const navmap_client_options* options, const char** error);

/* Waits up to timeout_ms for the next frame, (re)connecting as needed. A frame still held is
 * released first. Returns NAVMAP_CLIENT_FRAME with *frame filled in, NAVMAP_CLIENT_TIMEOUT,
 * NAVMAP_CLIENT_DISCONNECTED or NAVMAP_CLIENT_ERROR. Hold a frame for less than navmapd's stall
 * timeout (client_timeout_s, 5 s by default), or it drops the connection. */
NAVMAP_CLIENT_EXPORT int navmap_client_next_frame(navmap_client* client, int timeout_ms, navmap_frame* frame);

/* Gives the held frame back (its pixels must not be read afterwards). NAVMAP_CLIENT_FRAME: it was
 * unchanged all the time; NAVMAP_CLIENT_OVERWRITTEN: every slot of the ring was held at once and
 * the server overwrote it; NAVMAP_CLIENT_ERROR: `frame` is not the frame held. */
NAVMAP_CLIENT_EXPORT int navmap_client_release_frame(navmap_client* client, const navmap_frame* frame);

/* Asks navmapd for each frame's metadata block from the next connection on: call it after
 * navmap_client_create(), before the first navmap_client_next_frame(). 0, or NAVMAP_CLIENT_ERROR
 * when the client is null or already connected. */
NAVMAP_CLIENT_EXPORT int navmap_client_request_meta(navmap_client* client, int on);

/* Asks navmapd for dma-buf frames from the next connection on (docs/frame-protocol.md "dma-buf
 * frames"), falling back to the shared-memory ring when it refuses them (a renderer that cannot
 * export). With dma-buf frames a navmap_frame's pixels are a read-only mapping of the exported
 * buffer (stride: the buffer's), and navmap_client_frame_dmabuf() gives the buffer to import
 * instead. Call it after navmap_client_create(), before the first navmap_client_next_frame(). 0,
 * or NAVMAP_CLIENT_ERROR when the client is null or connected. */
NAVMAP_CLIENT_EXPORT int navmap_client_request_dmabuf(navmap_client* client);

/* The exported buffer of a dma-buf frame, for EGL_EXT_image_dma_buf_import or zwp_linux_dmabuf_v1. */
typedef struct navmap_dmabuf {
    int fd;            /* owned by the client: valid until the frame is released; dup() it to keep it */
    uint32_t fourcc;   /* DRM fourcc: 'AB24' (DRM_FORMAT_ABGR8888, RGBA bytes) */
    uint64_t modifier; /* DRM format modifier; 0: linear */
    uint32_t offset;   /* of plane 0 */
    uint32_t stride;   /* bytes per row of plane 0 */
    uint32_t buffer;   /* the buffer's index (0..15); `new_buffer` 1: this index has a new fd */
    int new_buffer;
} navmap_dmabuf;

/* The buffer of the frame held when it came as a dma-buf: NAVMAP_CLIENT_FRAME with *dmabuf filled;
 * NAVMAP_CLIENT_ERROR when `frame` is not the frame held or came through shared memory. */
NAVMAP_CLIENT_EXPORT int navmap_client_frame_dmabuf(const navmap_client* client, const navmap_frame* frame,
                                                    navmap_dmabuf* dmabuf);

/* The payload of the current connection, "shm" or "dmabuf"; "" while not connected. */
NAVMAP_CLIENT_EXPORT const char* navmap_client_payload(const navmap_client* client);

/* Why a dma-buf request fell back to shm on the current connection (navmapd's refusal); "" when
 * it did not or while not connected. Valid until the next call on this client. */
NAVMAP_CLIENT_EXPORT const char* navmap_client_payload_fallback(const navmap_client* client);

/* The validity of the frame held (header bytes every navmapd frame carries, no request needed).
 * NAVMAP_CLIENT_FRAME with *validity filled, NAVMAP_CLIENT_ERROR when `frame` is not the frame held. */
NAVMAP_CLIENT_EXPORT int navmap_client_frame_validity(const navmap_client* client, const navmap_frame* frame,
                                                      navmap_frame_validity* validity);

/* The metadata of the frame held: NAVMAP_CLIENT_FRAME with *meta filled; NAVMAP_CLIENT_TIMEOUT (0)
 * when the frame came without a block (not asked for, or the server had none for it);
 * NAVMAP_CLIENT_ERROR when `frame` is not the frame held. The library checked the block
 * (docs/frame-protocol.md): a malformed one ends the connection instead. */
NAVMAP_CLIENT_EXPORT int navmap_client_frame_meta(const navmap_client* client, const navmap_frame* frame,
                                                  navmap_frame_meta* meta);

/* 1 while connected, else 0. */
NAVMAP_CLIENT_EXPORT int navmap_client_connected(const navmap_client* client);

/* Why the last connection attempt failed or the stream ended ("" when nothing failed). Valid until
 * the next call on this client. */
NAVMAP_CLIENT_EXPORT const char* navmap_client_last_error(const navmap_client* client);

NAVMAP_CLIENT_EXPORT void navmap_client_get_stats(const navmap_client* client, navmap_client_stats* stats);

/* Closes the connection and frees the client (NULL is ignored). */
NAVMAP_CLIENT_EXPORT void navmap_client_destroy(navmap_client* client);

/* NOLINTEND(readability-identifier-naming) */

#ifdef __cplusplus
}
#endif

#endif /* NAVMAP_CLIENT_H */
