// SPDX-License-Identifier: Apache-2.0
#pragma once
// writeFramePng: saves a received frame (RGBA8 or RGB565) as an 8-bit RGBA PNG through
// OpenImageIO, for navmap-view and tests (library navmap_frame_png, which links OpenImageIO: the
// daemon and the client library do not).

#include <cstdint>
#include <string>

#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/net/result.h"

namespace navmap::ipc {

/// Writes `pixels` described by `header` as a PNG; the Error names the path and OpenImageIO's
/// reason.
Status writeFramePng(const std::string& path, const FrameHeader& header, const std::uint8_t* pixels);

}  // namespace navmap::ipc
