/* SPDX-License-Identifier: Apache-2.0 */
/* GstNavmapFrameMeta: what navmapsrc attaches to each buffer beside the pixels (docs/gstreamer.md
 * "Frame metadata"): the frame's validity from its header (docs/frame-protocol.md "Frame
 * validity") and, when the frame came with one, its guidance metadata block ("Metadata block").
 * For applications in C or C++ that read buffers of navmapsrc (an appsink, a pad probe):
 *
 *     const GstNavmapFrameMeta* m = gst_buffer_get_navmap_frame_meta(buffer);
 *     if (m != NULL && (m->flags & GST_NAVMAP_VALID_STALE_POSE)) warn_driver();
 *
 * Header only: the plugin registers the meta when it loads; before that no buffer can carry it and
 * gst_buffer_get_navmap_frame_meta() returns NULL. The meta has no tags and copies itself on every
 * buffer copy (its transform function), so it stays on the buffer through elements that copy or
 * pass it through (videoconvert, queue, tee). */
#ifndef NAVMAP_GST_NAVMAP_FRAME_META_H
#define NAVMAP_GST_NAVMAP_FRAME_META_H

#include <gst/gst.h>

G_BEGIN_DECLS

#define GST_NAVMAP_FRAME_META_API_NAME "GstNavmapFrameMetaAPI"
#define GST_NAVMAP_FRAME_META_INFO_NAME "GstNavmapFrameMeta"

/* Validity flags (frame header byte 69); none set = fresh. */
#define GST_NAVMAP_VALID_STALE_POSE 1u /* no pose for more than navmapd's stale_pose_ms (or none yet) */
#define GST_NAVMAP_VALID_DEGRADED 2u   /* something under the camera is missing: see `degraded` */
#define GST_NAVMAP_VALID_OFF_ROUTE 4u  /* guidance says the vehicle left its route */
/* Degraded reasons (header bytes 70..71). */
#define GST_NAVMAP_DEGRADED_TILES_MISSING 1u
#define GST_NAVMAP_DEGRADED_TILES_FAILED 2u
#define GST_NAVMAP_DEGRADED_ROAD_GRAPH_OFF 4u
#define GST_NAVMAP_DEGRADED_ORTHOIMAGE_OFF 8u
/* pose_age_ms when there has been no pose at all. */
#define GST_NAVMAP_POSE_AGE_NONE G_MAXUINT32

typedef struct _GstNavmapFrameMeta {
    GstMeta meta;

    guint64 sequence; /* the frame header's sequence */

    /* Validity (every frame of a navmapd that reports it). */
    gboolean validity_known; /* FALSE: the server reports no validity; the three below are 0 */
    guint flags;             /* GST_NAVMAP_VALID_*; 0 = fresh */
    guint degraded;          /* GST_NAVMAP_DEGRADED_*, non-zero exactly with GST_NAVMAP_VALID_DEGRADED */
    guint32 pose_age_ms;     /* ms from the newest pose fix to the render; GST_NAVMAP_POSE_AGE_NONE: none yet */

    /* The metadata block: has_block FALSE when the frame came without one (property meta=false,
     * or the server had none for it); every field below is then 0 or "". Strings are UTF-8, owned
     * by the meta, never NULL. */
    gboolean has_block;
    gboolean has_pose; /* FALSE: no fix yet (the pose fields are 0) */
    gdouble lat_deg;
    gdouble lon_deg;
    gdouble heading_deg;     /* clockwise from north, [0, 360) */
    gint64 pose_time_ns;     /* CLOCK_REALTIME ns of the CAN data behind the pose */
    gboolean has_next;       /* FALSE: no next manoeuvre (no route, arrived, off the route) */
    gchar* next_type;        /* "turn_left", "roundabout", ... (docs/ipc.md); "" without one */
    gint next_exit;          /* roundabout exit, 1..; 0 none */
    gdouble next_distance_m; /* along the route to its junction */
    gchar* next_street;      /* the street the next manoeuvre turns into; "" unknown */
    gint lane_count;         /* -1: lanes unknown; else lanes[0..lane_count) left to right */
    guint8 lanes[16];        /* bits 0..5 left, slight left, straight, slight right, right, u-turn; bit 7 take it */
    gboolean has_remaining;  /* FALSE: no route followed */
    gdouble remaining_m;
    gdouble remaining_s;
    gchar* current_street; /* the map-matched road's name; "" unknown */
    guint speed_limit_kmh; /* 0: unknown */
} GstNavmapFrameMeta;

/* The meta's API type; 0 while the plugin is not loaded (no buffer carries the meta then). */
static inline GType gst_navmap_frame_meta_api_get_type(void) {
    return g_type_from_name(GST_NAVMAP_FRAME_META_API_NAME);
}

/* The buffer's GstNavmapFrameMeta, or NULL when it has none. */
static inline GstNavmapFrameMeta* gst_buffer_get_navmap_frame_meta(GstBuffer* buffer) {
    const GType api = gst_navmap_frame_meta_api_get_type();
    return api != 0 ? (GstNavmapFrameMeta*)gst_buffer_get_meta(buffer, api) : NULL;
}

G_END_DECLS

#endif /* NAVMAP_GST_NAVMAP_FRAME_META_H */
