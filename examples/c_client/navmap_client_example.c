// SPDX-License-Identifier: Apache-2.0
/* navmap-client-example: a display process in C, as an HMI integrator writes one against
 * libnavmap-client (navmap_client.h). It connects to navmapd's frame socket with a profile,
 * keeps reconnecting (with backoff) while navmapd is not there, and reads each frame in place in
 * the shared-memory ring, without copying it, until it releases it.
 *
 *   navmap-client-example SOCKET [PROFILE [FRAMES [SECONDS]]]
 *
 * Prints three lines per frame: "frame SEQ WxH stride S pixel R,G,B,A" (the top-left pixel; RGBA8),
 * its validity ("validity SEQ fresh pose_age_ms 40 degraded -") and its guidance metadata, asked for
 * with navmap_client_request_meta() ("meta SEQ pose LAT,LON heading H next TYPE exit E in D m onto
 * "STREET" lanes L remaining M m S s street "STREET" speed_limit K", absent parts "none" or
 * "unknown"; "meta SEQ none" for a frame without a block); at the end "frames N connects C
 * failed_attempts F disconnects D held_overwritten H". Exit status 0 when FRAMES frames arrived
 * within SECONDS (default 10 frames, 30 s), 1 when not, 2 on usage. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */ /* NOLINT(bugprone-reserved-identifier): POSIX asks for it */

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "navmap_client.h"

/* "fresh", or the flags joined with '+' ("stale_pose+off_route"); "unknown" from a server without
 * validity. */
static void print_validity(unsigned long long seq, const navmap_frame_validity* v) {
    static const char* const flag_names[] = {"stale_pose", "degraded", "off_route"};
    static const char* const reason_names[] = {"tiles_missing", "tiles_failed", "road_graph_off", "orthoimage_off"};
    printf("validity %llu ", seq);
    if (!v->known) {
        printf("unknown\n");
        return;
    }
    if (v->flags == 0) {
        printf("fresh");
    }
    for (unsigned i = 0, n = 0; i < 3; ++i) {
        if (v->flags & (1u << i)) {
            printf("%s%s", n++ ? "+" : "", flag_names[i]);
        }
    }
    if (v->pose_age_ms == NAVMAP_POSE_AGE_NONE) {
        printf(" pose_age_ms none degraded ");
    } else {
        printf(" pose_age_ms %u degraded ", (unsigned)v->pose_age_ms);
    }
    if (v->degraded == 0) {
        printf("-");
    }
    for (unsigned i = 0, n = 0; i < 4; ++i) {
        if (v->degraded & (1u << i)) {
            printf("%s%s", n++ ? "+" : "", reason_names[i]);
        }
    }
    printf("\n");
}

static void print_meta(unsigned long long seq, const navmap_frame_meta* m) {
    printf("meta %llu pose ", seq);
    if (m->has_pose) {
        printf("%.6f,%.6f heading %.2f", m->lat_deg, m->lon_deg, m->heading_deg);
    } else {
        printf("none");
    }
    if (m->has_next) {
        printf(" next %s exit %d in %.1f m onto \"%s\"", m->next_type, m->next_exit, m->next_distance_m,
               m->next_street);
    } else {
        printf(" next none");
    }
    if (m->lane_count < 0) {
        printf(" lanes unknown");
    } else {
        printf(" lanes");
        for (int i = 0; i < m->lane_count; ++i) {
            printf("%c%02x", i ? ',' : ' ', m->lanes[i]);
        }
    }
    if (m->has_remaining) {
        printf(" remaining %.1f m %.1f s", m->remaining_m, m->remaining_s);
    } else {
        printf(" remaining none");
    }
    printf(" street \"%s\" speed_limit ", m->current_street);
    if (m->speed_limit_kmh > 0) {
        printf("%d\n", m->speed_limit_kmh);
    } else {
        printf("unknown\n");
    }
}

static double now_s(void) {
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec / 1e9;
}

int main(int argc, char** argv) {
    if (argc < 2 || argc > 5) {
        fprintf(stderr, "usage: navmap-client-example SOCKET [PROFILE [FRAMES [SECONDS]]]\n");
        return 2;
    }
    navmap_client_options options;
    navmap_client_options_init(&options);
    options.socket_path = argv[1];
    options.profile = argc > 2 ? argv[2] : "cluster";
    options.reconnect_initial_ms = 50;
    options.reconnect_max_ms = 500;
    const long want = argc > 3 ? strtol(argv[3], NULL, 10) : 10;
    const double seconds = argc > 4 ? strtod(argv[4], NULL) : 30.0;
    if (want < 1 || !(seconds > 0.0)) {
        fprintf(stderr, "navmap-client-example: FRAMES must be >= 1 and SECONDS > 0\n");
        return 2;
    }
    const char* error = NULL;
    navmap_client* client = navmap_client_create(&options, &error);
    if (client == NULL) {
        fprintf(stderr, "navmap-client-example: %s\n", error);
        return 2;
    }
    navmap_client_request_meta(client, 1); /* each frame's guidance metadata block */
    printf("libnavmap-client %s (headers %s)\n", navmap_client_version(), NAVMAP_VERSION);
    long got = 0;
    int waiting = 0; /* 1 after "waiting" was printed, until a frame arrives */
    const double end = now_s() + seconds;
    while (got < want && now_s() < end) {
        navmap_frame frame;
        const int r = navmap_client_next_frame(client, 200, &frame);
        if (r == NAVMAP_CLIENT_FRAME) {
            const uint8_t* p = frame.pixels; /* top-left pixel, read in place in the ring */
            printf("frame %llu %ux%u stride %u pixel %u,%u,%u,%u\n", (unsigned long long)frame.sequence, frame.width,
                   frame.height, frame.stride, p[0], p[1], p[2], p[3]);
            navmap_frame_validity validity;
            if (navmap_client_frame_validity(client, &frame, &validity) == NAVMAP_CLIENT_FRAME) {
                print_validity((unsigned long long)frame.sequence, &validity);
            }
            navmap_frame_meta meta;
            if (navmap_client_frame_meta(client, &frame, &meta) == NAVMAP_CLIENT_FRAME) {
                print_meta((unsigned long long)frame.sequence, &meta);
            } else {
                printf("meta %llu none\n", (unsigned long long)frame.sequence);
            }
            if (navmap_client_release_frame(client, &frame) == NAVMAP_CLIENT_OVERWRITTEN) {
                printf("frame %llu was overwritten while held\n", (unsigned long long)frame.sequence);
            }
            ++got;
            waiting = 0;
        } else if (r == NAVMAP_CLIENT_DISCONNECTED && !waiting) {
            printf("waiting: %s\n", navmap_client_last_error(client));
            waiting = 1;
        } else if (r == NAVMAP_CLIENT_ERROR) {
            fprintf(stderr, "navmap-client-example: bad arguments\n");
            break;
        }
        fflush(stdout);
    }
    navmap_client_stats stats;
    navmap_client_get_stats(client, &stats);
    printf("frames %llu connects %llu failed_attempts %llu disconnects %llu held_overwritten %llu\n",
           (unsigned long long)stats.frames, (unsigned long long)stats.connects,
           (unsigned long long)stats.failed_attempts, (unsigned long long)stats.disconnects,
           (unsigned long long)stats.held_overwritten);
    navmap_client_destroy(client);
    return got >= want ? 0 : 1;
}
