// SPDX-License-Identifier: Apache-2.0
/* navmap-client-example: a display process in C, as an HMI integrator writes one against
 * libnavmap-client (navmap_client.h). It connects to navmapd's frame socket with a profile,
 * keeps reconnecting (with backoff) while navmapd is not there, and reads each frame in place in
 * the shared-memory ring, without copying it, until it releases it.
 *
 *   navmap-client-example SOCKET [PROFILE [FRAMES [SECONDS]]]
 *
 * Prints one line per frame ("frame SEQ WxH stride S pixel R,G,B,A" of the top-left pixel; RGBA8),
 * then "frames N connects C failed_attempts F disconnects D held_overwritten H". Exit status 0
 * when FRAMES frames arrived within SECONDS (default 10 frames, 30 s), 1 when not, 2 on usage. */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */ /* NOLINT(bugprone-reserved-identifier): POSIX asks for it */

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "navmap_client.h"

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
