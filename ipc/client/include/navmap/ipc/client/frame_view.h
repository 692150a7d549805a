// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameView: a rendered frame as the render thread hands it to FrameServer::publish() (not owned).

#include <cstdint>
#include <memory>
#include <vector>

#include "navmap/ipc/client/frame_format.h"
#include "navmap/ipc/client/frame_meta.h"

namespace navmap::ipc {

struct FrameView {
    const std::uint8_t* pixels = nullptr;  ///< first byte of the top row
    int width = 0;
    int height = 0;
    int stride = 0;  ///< bytes per row (0 = tightly packed)
    PixelFormat format = PixelFormat::Rgba8;
    std::int64_t render_time_ns = 0;  ///< CLOCK_REALTIME ns; 0 = "now" at publish
    std::int64_t source_time_ns =
        0;  ///< CLOCK_REALTIME ns the CAN data of the pose arrived (VehicleSample::source_time)
    /// Whether the frame can be trusted; goes into every header of it (ring slot included).
    FrameValidity validity;
    /// The frame's metadata block (encodeFrameMeta), sent after its header to the clients that
    /// asked for it; null: none (those clients get the frame without a block).
    std::shared_ptr<const std::vector<std::uint8_t>> meta;
};

}  // namespace navmap::ipc
