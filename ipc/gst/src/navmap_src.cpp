// SPDX-License-Identifier: Apache-2.0
#include "navmap_src.h"

#include <algorithm>
#include <chrono>

#include "frame_buffer.h"
#include "navmap_frame_meta.h"

GST_DEBUG_CATEGORY_STATIC(navmap_src_debug);
#define GST_CAT_DEFAULT navmap_src_debug

// G_DEFINE_TYPE's parent pointer, class init and instance init are C names.
G_DEFINE_TYPE(GstNavmapSrc, gst_navmap_src, GST_TYPE_PUSH_SRC)

namespace navmap::ipc::gst {

namespace {

constexpr std::chrono::milliseconds kWaitSlice{100};  // the longest a create() waits between flush checks

GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("video/x-raw, format=(string)RGBA, width=(int)[16, 4096], height=(int)[16, 4096], "
                    "framerate=(fraction)[0/1, 1000/1], pixel-aspect-ratio=(fraction)1/1"));

NavmapSrcState& stateOf(gpointer object) { return *GST_NAVMAP_SRC(object)->state; }

GstClockTime frameDuration(int fps) {
    return fps > 0 ? gst_util_uint64_scale_int(GST_SECOND, 1, fps) : GST_CLOCK_TIME_NONE;
}

GstCaps* capsFor(int width, int height, int fps) {
    return gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, "RGBA", "width", G_TYPE_INT, width, "height",
                               G_TYPE_INT, height, "framerate", GST_TYPE_FRACTION, fps, 1, "pixel-aspect-ratio",
                               GST_TYPE_FRACTION, 1, 1, nullptr);
}

/// The pipeline's running time now; 0 without a clock.
GstClockTime runningTimeNow(GstElement* element) {
    GstClock* clock = gst_element_get_clock(element);
    if (clock == nullptr) {
        return 0;
    }
    const GstClockTime now = gst_clock_get_time(clock);
    gst_object_unref(clock);
    const GstClockTime base = gst_element_get_base_time(element);
    return now > base ? now - base : 0;
}

void finalize(GObject* object) {
    delete GST_NAVMAP_SRC(object)->state;
    G_OBJECT_CLASS(gst_navmap_src_parent_class)->finalize(object);
}

void setProperty(GObject* object, guint id, const GValue* value, GParamSpec* pspec) {
    setNavmapSrcProperty(stateOf(object), id, value, pspec, object);
}

void getProperty(GObject* object, guint id, GValue* value, GParamSpec* pspec) {
    getNavmapSrcProperty(stateOf(object), id, value, pspec, object);
}

gboolean start(GstBaseSrc* base) {
    auto& st = stateOf(base);
    SourceSettings settings;
    {
        std::lock_guard lock(st.lock);
        const auto& p = st.props;
        auto request = makeStreamRequest(p.profile, p.width, p.height, p.fps, p.view, p.transport);
        if (!request) {
            GST_ELEMENT_ERROR(base, RESOURCE, SETTINGS, ("%s", request.error().message.c_str()), (nullptr));
            return FALSE;
        }
        settings.request = request.value();
        settings.request.meta = p.meta;
        st.post_messages = p.post_messages;
        settings.socket_path = p.socket_path;
        settings.host = p.host;
        settings.port = p.port;
        settings.reconnect = p.reconnect;
    }
    const std::string where =
        settings.port >= 0 ? settings.host + ":" + std::to_string(settings.port) : settings.socket_path;
    auto source = std::make_unique<FrameSource>(std::move(settings));
    if (auto opened = source->open(); !opened) {
        GST_ELEMENT_ERROR(base, RESOURCE, OPEN_READ,
                          ("Could not receive navmapd's frames: %s", opened.message().c_str()),
                          ("frame socket %s", where.c_str()));
        return FALSE;
    }
    const auto& profile = source->profile();
    GST_INFO_OBJECT(base, "profile %s %dx%d at %d fps from %s (%s)", profile.name.c_str(), profile.width,
                    profile.height, profile.fps, where.c_str(), streamPayloadName(source->settings().request.payload));
    st.caps_width = profile.width;
    st.caps_height = profile.height;
    st.caps_fps = profile.fps;
    st.anchored_connects = 0;
    st.last_pts = GST_CLOCK_TIME_NONE;
    st.frames = 0;
    st.reported_error.clear();
    st.source = std::move(source);
    return TRUE;
}

gboolean stop(GstBaseSrc* base) {
    stateOf(base).source.reset();
    return TRUE;
}

GstCaps* getCaps(GstBaseSrc* base, GstCaps* filter) {
    auto& st = stateOf(base);
    GstCaps* caps = st.caps_width > 0 ? capsFor(st.caps_width, st.caps_height, st.caps_fps)
                                      : gst_pad_get_pad_template_caps(GST_BASE_SRC_PAD(base));
    if (filter != nullptr) {
        GstCaps* both = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
        gst_caps_unref(caps);
        caps = both;
    }
    return caps;
}

gboolean query(GstBaseSrc* base, GstQuery* q) {
    if (GST_QUERY_TYPE(q) == GST_QUERY_LATENCY) {
        // Live: a frame is pushed when it has arrived, at most one frame period after its time.
        const GstClockTime period = frameDuration(stateOf(base).caps_fps);
        gst_query_set_latency(q, TRUE, GST_CLOCK_TIME_IS_VALID(period) ? period : 0, GST_CLOCK_TIME_NONE);
        return TRUE;
    }
    return GST_BASE_SRC_CLASS(gst_navmap_src_parent_class)->query(base, q);
}

gboolean unlock(GstBaseSrc* base) {
    stateOf(base).flushing = true;
    return TRUE;
}

gboolean unlockStop(GstBaseSrc* base) {
    stateOf(base).flushing = false;
    return TRUE;
}

/// New caps when a frame's size is not the negotiated one (the library checks frames against the
/// granted profile, so this is a safeguard rather than a path taken).
bool followFrameSize(GstBaseSrc* base, NavmapSrcState& st, const FrameHeader& h) {
    if (static_cast<int>(h.width) == st.caps_width && static_cast<int>(h.height) == st.caps_height) {
        return true;
    }
    GST_INFO_OBJECT(base, "frames are now %ux%u (were %dx%d): renegotiating", h.width, h.height, st.caps_width.load(),
                    st.caps_height.load());
    st.caps_width = static_cast<int>(h.width);
    st.caps_height = static_cast<int>(h.height);
    GstCaps* caps = capsFor(st.caps_width, st.caps_height, st.caps_fps);
    const gboolean ok = gst_base_src_set_caps(base, caps);
    gst_caps_unref(caps);
    return ok != FALSE;
}

/// PTS, duration, offsets and DISCONT. The first frame of each connection anchors: its PTS is
/// the running time it arrived at (never before the previous frame's end); the frames after it
/// are that plus their render time's distance from the anchor's, kept increasing.
void stampBuffer(GstBaseSrc* base, NavmapSrcState& st, GstBuffer* buffer, const FrameHeader& h) {
    const GstClockTime duration = frameDuration(st.caps_fps);
    const std::uint64_t connects = st.source->connects();
    GstClockTime pts = 0;
    if (connects != st.anchored_connects) {
        st.anchored_connects = connects;
        st.anchor_render_ns = h.render_time_ns;
        st.anchor_running = runningTimeNow(GST_ELEMENT(base));
        if (GST_CLOCK_TIME_IS_VALID(st.last_pts)) {
            const GstClockTime after = st.last_pts + (GST_CLOCK_TIME_IS_VALID(duration) ? duration : 1);
            st.anchor_running = std::max(st.anchor_running, after);
        }
        pts = st.anchor_running;
        GST_BUFFER_FLAG_SET(buffer, GST_BUFFER_FLAG_DISCONT);
    } else {
        const std::int64_t since = h.render_time_ns - st.anchor_render_ns;
        pts = st.anchor_running + static_cast<GstClockTime>(std::max<std::int64_t>(since, 0));
        if (pts <= st.last_pts) {
            pts = st.last_pts + 1;
        }
    }
    st.last_pts = pts;
    GST_BUFFER_PTS(buffer) = pts;
    GST_BUFFER_DTS(buffer) = GST_CLOCK_TIME_NONE;
    GST_BUFFER_DURATION(buffer) = duration;
    GST_BUFFER_OFFSET(buffer) = st.frames;
    GST_BUFFER_OFFSET_END(buffer) = st.frames + 1;
    ++st.frames;
}

/// post-messages=true: the buffer's GstNavmapFrameMeta as the element message "navmap-frame", one
/// per frame (validity "unknown" for a frame without the meta).
void postFrameMessage(GstBaseSrc* base, const NavmapSrcState& st, GstBuffer* buffer, const FrameHeader& h) {
    if (!st.post_messages) {
        return;
    }
    const auto* meta =
        reinterpret_cast<const GstNavmapFrameMeta*>(gst_buffer_get_meta(buffer, navmapFrameMetaApiType()));
    GstStructure* s = navmapFrameStructure(meta, h.sequence, GST_BUFFER_PTS(buffer));
    gst_element_post_message(GST_ELEMENT(base), gst_message_new_element(GST_OBJECT(base), s));
}

/// Reconnect on: each new reason the stream is gone (or cannot be had) becomes a warning.
void reportLostConnection(GstBaseSrc* base, NavmapSrcState& st) {
    std::string why = st.source->lastError();
    if (why.empty() || why == st.reported_error) {
        return;
    }
    st.reported_error = why;
    GST_ELEMENT_WARNING(base, RESOURCE, READ, ("No frames from navmapd, reconnecting: %s", why.c_str()), (nullptr));
}

GstFlowReturn create(GstPushSrc* push, GstBuffer** out) {
    auto* base = GST_BASE_SRC(push);
    auto& st = stateOf(push);
    for (;;) {
        if (st.flushing) {
            return GST_FLOW_FLUSHING;
        }
        GstBuffer* buffer = nullptr;
        FrameHeader h;
        auto got = st.source->next(kWaitSlice, &buffer, &h);
        if (!got) {
            GST_ELEMENT_ERROR(base, STREAM, FAILED, ("navmapd's frame stream failed: %s", got.error().message.c_str()),
                              (nullptr));
            return GST_FLOW_ERROR;
        }
        reportLostConnection(base, st);
        if (got.value() == NextFrame::Ended) {
            GST_INFO_OBJECT(base, "navmapd closed the stream after %" G_GUINT64_FORMAT " frames: EOS", st.frames);
            return GST_FLOW_EOS;
        }
        if (got.value() == NextFrame::Timeout) {
            continue;
        }
        if (!followFrameSize(base, st, h)) {
            gst_buffer_unref(buffer);
            return GST_FLOW_NOT_NEGOTIATED;
        }
        stampBuffer(base, st, buffer, h);
        postFrameMessage(base, st, buffer, h);
        *out = buffer;
        return GST_FLOW_OK;
    }
}

}  // namespace

}  // namespace navmap::ipc::gst

// NOLINTNEXTLINE(readability-identifier-naming): G_DEFINE_TYPE names it
static void gst_navmap_src_class_init(GstNavmapSrcClass* klass) {
    using namespace navmap::ipc::gst;
    auto* object_class = G_OBJECT_CLASS(klass);
    auto* element_class = GST_ELEMENT_CLASS(klass);
    auto* base_class = GST_BASE_SRC_CLASS(klass);
    object_class->finalize = finalize;
    object_class->set_property = setProperty;
    object_class->get_property = getProperty;
    installNavmapSrcProperties(object_class);
    gst_element_class_set_static_metadata(
        element_class, "navmap frame source", "Source/Video",
        "Receives navmapd's rendered map frames (shared memory, raw or zlib) through libnavmap-client",
        "navmap maintainers <navmap@localhost>");
    gst_element_class_add_static_pad_template(element_class, &src_template);
    base_class->start = start;
    base_class->stop = stop;
    base_class->get_caps = getCaps;
    base_class->query = query;
    base_class->unlock = unlock;
    base_class->unlock_stop = unlockStop;
    GST_PUSH_SRC_CLASS(klass)->create = create;
    GST_DEBUG_CATEGORY_INIT(navmap_src_debug, "navmapsrc", 0, "navmap frame source");
}

// NOLINTNEXTLINE(readability-identifier-naming): G_DEFINE_TYPE names it
static void gst_navmap_src_init(GstNavmapSrc* self) {
    self->state = new navmap::ipc::gst::NavmapSrcState();
    gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
    gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
    gst_base_src_set_do_timestamp(GST_BASE_SRC(self), FALSE);
}
