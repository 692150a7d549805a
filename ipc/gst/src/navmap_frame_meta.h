// SPDX-License-Identifier: Apache-2.0
#pragma once
// The plugin's side of GstNavmapFrameMeta (public header navmap/gst/navmap_frame_meta.h): its
// registration (the API type once, with no tags; the meta info with init, free and a transform
// that copies it on every buffer copy), filling it from a frame header and metadata block, and the
// GstStructure of the element message "navmap-frame" (docs/gstreamer.md "Frame metadata").

#include <gst/gst.h>

#include "navmap/gst/navmap_frame_meta.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_meta.h"

namespace navmap::ipc::gst {

/// Registers the API type (once) and returns it.
GType navmapFrameMetaApiType();
/// Registers the meta (once) and returns its info.
const GstMetaInfo* navmapFrameMetaInfo();

/// Attaches a GstNavmapFrameMeta to `buffer`: the header's sequence and validity, and `block`'s
/// fields when there is one. Nothing when the header carries no validity and there is no block
/// (a server from before both). Returns the meta or nullptr.
GstNavmapFrameMeta* addNavmapFrameMeta(GstBuffer* buffer, const FrameHeader& header, const FrameMeta* block);

/// "navmap-frame": frame `sequence`'s meta fields (docs/gstreamer.md lists them) and `pts`, for an
/// element message; `meta` nullptr (a frame without either): validity "unknown", no block. The
/// caller owns it.
GstStructure* navmapFrameStructure(const GstNavmapFrameMeta* meta, std::uint64_t sequence, GstClockTime pts);

}  // namespace navmap::ipc::gst
