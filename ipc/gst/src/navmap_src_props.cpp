// SPDX-License-Identifier: Apache-2.0
// navmapsrc's properties: where navmapd is, which profile, how the pixels travel, reconnect, the
// metadata block and its messages.
#include "navmap_src.h"

namespace navmap::ipc::gst {

namespace {

enum Property : guint {
    kPropSocket = 1,
    kPropHost,
    kPropPort,
    kPropProfile,
    kPropWidth,
    kPropHeight,
    kPropFps,
    kPropView,
    kPropTransport,
    kPropReconnect,
    kPropMeta,
    kPropPostMessages,
};

constexpr auto kFlags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS | GST_PARAM_MUTABLE_READY);

GType transportType() {
    static GType type = 0;
    if (g_once_init_enter(&type)) {
        static const GEnumValue kValues[] = {
            {static_cast<gint>(StreamPayload::Shm), "Shared-memory ring (Unix socket only)", "shm"},
            {static_cast<gint>(StreamPayload::Raw), "Uncompressed pixels on the socket", "raw"},
            {static_cast<gint>(StreamPayload::Zlib), "zlib-compressed pixels on the socket", "zlib"},
            {0, nullptr, nullptr},
        };
        const GType t = g_enum_register_static("GstNavmapTransport", kValues);
        gst_type_mark_as_plugin_api(t, static_cast<GstPluginAPIFlags>(0));
        g_once_init_leave(&type, t);
    }
    return type;
}

std::string stringOf(const GValue* value) {
    const char* s = g_value_get_string(value);
    return s != nullptr ? s : "";
}

}  // namespace

void installNavmapSrcProperties(GObjectClass* klass) {
    g_object_class_install_property(
        klass, kPropSocket,
        g_param_spec_string("socket", "Socket", "navmapd's Unix frame socket (used when port is -1)",
                            "/run/navmap/frames.sock", kFlags));
    g_object_class_install_property(
        klass, kPropHost,
        g_param_spec_string("host", "Host", "Host of navmapd's TCP frame server (with port; transport raw or zlib)",
                            nullptr, kFlags));
    g_object_class_install_property(
        klass, kPropPort,
        g_param_spec_int("port", "Port", "TCP port of navmapd's frame server; -1: the Unix socket", -1, 65535, -1,
                         kFlags));
    g_object_class_install_property(
        klass, kPropProfile,
        g_param_spec_string("profile", "Profile",
                            "Display profile: cluster (1280x480 snail), hud (800x240 hud), center (1280x720 bird) or "
                            "another name with width, height and view",
                            "cluster", kFlags));
    g_object_class_install_property(klass, kPropWidth,
                                    g_param_spec_int("width", "Width", "Frame width in pixels; 0: the profile's", 0,
                                                     kMaxStreamDimension, 0, kFlags));
    g_object_class_install_property(klass, kPropHeight,
                                    g_param_spec_int("height", "Height", "Frame height in pixels; 0: the profile's", 0,
                                                     kMaxStreamDimension, 0, kFlags));
    g_object_class_install_property(
        klass, kPropFps,
        g_param_spec_int("fps", "Frames per second",
                         "Most frames per second wanted (the caps' framerate); -1: the profile's (30); 0: every "
                         "frame rendered (framerate 0/1)",
                         -1, kMaxStreamFps, -1, kFlags));
    g_object_class_install_property(
        klass, kPropView,
        g_param_spec_string("view", "View", "bird, snail or hud; empty: the profile's", nullptr, kFlags));
    g_object_class_install_property(klass, kPropTransport,
                                    g_param_spec_enum("transport", "Transport", "How the pixels travel",
                                                      transportType(), static_cast<gint>(StreamPayload::Shm), kFlags));
    g_object_class_install_property(
        klass, kPropReconnect,
        g_param_spec_boolean("reconnect", "Reconnect",
                             "Connect again with backoff (100 ms doubling to 5 s) when navmapd is not there or goes "
                             "away, instead of an error or EOS",
                             FALSE, kFlags));
    g_object_class_install_property(
        klass, kPropMeta,
        g_param_spec_boolean(
            "meta", "Metadata",
            "Ask navmapd for each frame's guidance metadata (pose, next manoeuvre, streets) and put it "
            "into the buffer's GstNavmapFrameMeta beside the validity",
            TRUE, kFlags));
    g_object_class_install_property(
        klass, kPropPostMessages,
        g_param_spec_boolean("post-messages", "Post messages",
                             "Post each frame's validity and metadata as an element message navmap-frame", FALSE,
                             kFlags));
}

void setNavmapSrcProperty(NavmapSrcState& state, guint id, const GValue* value, GParamSpec* pspec, GObject* object) {
    std::lock_guard lock(state.lock);
    auto& p = state.props;
    switch (id) {
        case kPropSocket: p.socket_path = stringOf(value); break;
        case kPropHost: p.host = stringOf(value); break;
        case kPropPort: p.port = g_value_get_int(value); break;
        case kPropProfile: p.profile = stringOf(value); break;
        case kPropWidth: p.width = g_value_get_int(value); break;
        case kPropHeight: p.height = g_value_get_int(value); break;
        case kPropFps: p.fps = g_value_get_int(value); break;
        case kPropView: p.view = stringOf(value); break;
        case kPropTransport: p.transport = static_cast<StreamPayload>(g_value_get_enum(value)); break;
        case kPropReconnect: p.reconnect = g_value_get_boolean(value) != FALSE; break;
        case kPropMeta: p.meta = g_value_get_boolean(value) != FALSE; break;
        case kPropPostMessages: p.post_messages = g_value_get_boolean(value) != FALSE; break;
        default: G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec); break;
    }
}

void getNavmapSrcProperty(NavmapSrcState& state, guint id, GValue* value, GParamSpec* pspec, GObject* object) {
    std::lock_guard lock(state.lock);
    const auto& p = state.props;
    const auto or_null = [](const std::string& s) { return s.empty() ? nullptr : s.c_str(); };
    switch (id) {
        case kPropSocket: g_value_set_string(value, p.socket_path.c_str()); break;
        case kPropHost: g_value_set_string(value, or_null(p.host)); break;
        case kPropPort: g_value_set_int(value, p.port); break;
        case kPropProfile: g_value_set_string(value, p.profile.c_str()); break;
        case kPropWidth: g_value_set_int(value, p.width); break;
        case kPropHeight: g_value_set_int(value, p.height); break;
        case kPropFps: g_value_set_int(value, p.fps); break;
        case kPropView: g_value_set_string(value, or_null(p.view)); break;
        case kPropTransport: g_value_set_enum(value, static_cast<gint>(p.transport)); break;
        case kPropReconnect: g_value_set_boolean(value, p.reconnect ? TRUE : FALSE); break;
        case kPropMeta: g_value_set_boolean(value, p.meta ? TRUE : FALSE); break;
        case kPropPostMessages: g_value_set_boolean(value, p.post_messages ? TRUE : FALSE); break;
        default: G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec); break;
    }
}

}  // namespace navmap::ipc::gst
