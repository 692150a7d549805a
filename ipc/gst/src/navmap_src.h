// SPDX-License-Identifier: Apache-2.0
#pragma once
// navmapsrc (GstNavmapSrc): a live GStreamer source of navmapd's frames (docs/gstreamer.md). A
// GstPushSrc whose streaming thread receives frames through FrameSource (libnavmap-client) and
// pushes them as video/x-raw,format=RGBA, timestamped in running time from the frame headers'
// render times. Waits for a frame at most 100 ms at a time, so a flush or a state change never
// waits on navmapd.

#include <gst/base/gstpushsrc.h>
#include <gst/gst.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <string>

#include "frame_source.h"

namespace navmap::ipc::gst {

/// navmapsrc's properties (navmap_src_props.cpp); guarded by NavmapSrcState::lock.
struct NavmapSrcProps {
    std::string socket_path = "/run/navmap/frames.sock";
    std::string host;
    int port = -1;
    std::string profile = "cluster";
    int width = 0;   ///< 0: the profile's
    int height = 0;  ///< 0: the profile's
    int fps = -1;    ///< -1: the profile's; 0: every frame
    std::string view;
    StreamPayload transport = StreamPayload::Shm;
    bool reconnect = false;
    bool meta = true;            ///< ask for the metadata block ("meta":true)
    bool post_messages = false;  ///< post each frame's GstNavmapFrameMeta as an element message
};

/// The element's C++ state (the GObject instance holds a pointer to it).
struct NavmapSrcState {
    std::mutex lock;
    NavmapSrcProps props;
    std::unique_ptr<FrameSource> source;  // from start() to stop(); the streaming thread's
    std::atomic<bool> flushing{false};
    bool post_messages = false;  // props.post_messages at start(); the streaming thread's
    // Caps now set (width, height, fps of the granted profile or the newest frame): written by
    // start() and the streaming thread, read by caps and latency queries from any thread.
    std::atomic<int> caps_width{0};
    std::atomic<int> caps_height{0};
    std::atomic<int> caps_fps{0};
    // Timestamps: the first frame of each connection anchors its render time to the running time
    // it arrived at (docs/gstreamer.md "Timestamps").
    std::uint64_t anchored_connects = 0;
    std::int64_t anchor_render_ns = 0;
    GstClockTime anchor_running = 0;
    GstClockTime last_pts = GST_CLOCK_TIME_NONE;
    std::uint64_t frames = 0;
    std::string reported_error;  // reconnect on: the newest lost-connection reason posted as a warning
};

void installNavmapSrcProperties(GObjectClass* klass);
void setNavmapSrcProperty(NavmapSrcState& state, guint id, const GValue* value, GParamSpec* pspec, GObject* object);
void getNavmapSrcProperty(NavmapSrcState& state, guint id, GValue* value, GParamSpec* pspec, GObject* object);

}  // namespace navmap::ipc::gst

G_BEGIN_DECLS
#define GST_TYPE_NAVMAP_SRC (gst_navmap_src_get_type())
G_DECLARE_FINAL_TYPE(GstNavmapSrc, gst_navmap_src, GST, NAVMAP_SRC, GstPushSrc)
G_END_DECLS

struct _GstNavmapSrc {
    GstPushSrc parent;
    navmap::ipc::gst::NavmapSrcState* state;
};
