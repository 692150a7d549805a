// SPDX-License-Identifier: Apache-2.0
#pragma once
// writeFramePng: saves a received frame (RGBA8 or RGB565) as an 8-bit RGBA PNG (zlib only, no
// image library), for navmap-view and tests.

#include <cstdint>
#include <string>
#include <vector>

#include "navmap/ipc/frame_header.h"
#include "navmap/ipc/result.h"

namespace navmap::ipc {

/// Encodes `pixels` described by `header` as PNG bytes.
std::vector<std::uint8_t> encodeFramePng(const FrameHeader& header, const std::uint8_t* pixels);
/// Writes the PNG; the Error names the path and the failed call.
Status writeFramePng(const std::string& path, const FrameHeader& header, const std::uint8_t* pixels);

}  // namespace navmap::ipc
