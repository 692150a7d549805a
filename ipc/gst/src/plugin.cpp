// SPDX-License-Identifier: Apache-2.0
// libgstnavmap.so: the GStreamer plugin "navmap" with the element navmapsrc (docs/gstreamer.md).
#include <gst/gst.h>

#include "navmap_frame_meta.h"
#include "navmap_src.h"

namespace {

gboolean pluginInit(GstPlugin* plugin) {
    // GstNavmapFrameMeta exists from the plugin's load on: applications look its API type up by name.
    navmap::ipc::gst::navmapFrameMetaInfo();
    return gst_element_register(plugin, "navmapsrc", GST_RANK_NONE, GST_TYPE_NAVMAP_SRC);
}

}  // namespace

#define PACKAGE "navmap"
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, navmap, "navmapd's rendered map frames as a video source",
                  pluginInit, NAVMAP_GST_VERSION, "Apache 2.0", "navmap", "localhost")
