// SPDX-License-Identifier: Apache-2.0
#pragma once
// makeFrameBuffer: the one place where navmapsrc fills a GstBuffer from a received frame. Pixels
// go in as tightly packed RGBA rows (GStreamer's default stride for the caps); the frame's validity
// and metadata block go onto the buffer here as a GstNavmapFrameMeta (navmap_frame_meta.h).
// Timestamps and flags are the element's (navmap_src.cpp).

#include <gst/gst.h>

#include <cstdint>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_meta.h"

namespace navmap::ipc::gst {

/// A new buffer of header.width * 4 * header.height bytes holding the frame at `pixels` (rows of
/// header.stride bytes, RGBA8), with a GstNavmapFrameMeta of the header's validity and `block`
/// (the frame's metadata block; nullptr: none). nullptr when the frame is not RGBA8.
GstBuffer* makeFrameBuffer(const FrameHeader& header, const std::uint8_t* pixels, const FrameMeta* block);

}  // namespace navmap::ipc::gst
