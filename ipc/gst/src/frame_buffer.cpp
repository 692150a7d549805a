// SPDX-License-Identifier: Apache-2.0
#include "frame_buffer.h"

#include <cstring>

#include "navmap_frame_meta.h"

namespace navmap::ipc::gst {

GstBuffer* makeFrameBuffer(const FrameHeader& header, const std::uint8_t* pixels, const FrameMeta* block) {
    if (header.format != PixelFormat::Rgba8) {
        return nullptr;
    }
    const std::size_t row_bytes = static_cast<std::size_t>(header.width) * 4;
    GstBuffer* buffer = gst_buffer_new_allocate(nullptr, row_bytes * header.height, nullptr);
    GstMapInfo map;
    if (buffer == nullptr || !gst_buffer_map(buffer, &map, GST_MAP_WRITE)) {
        if (buffer != nullptr) {
            gst_buffer_unref(buffer);
        }
        return nullptr;
    }
    if (header.stride == row_bytes) {
        std::memcpy(map.data, pixels, row_bytes * header.height);
    } else {
        for (std::uint32_t y = 0; y < header.height; ++y) {
            std::memcpy(map.data + y * row_bytes, pixels + static_cast<std::size_t>(y) * header.stride, row_bytes);
        }
    }
    gst_buffer_unmap(buffer, &map);
    addNavmapFrameMeta(buffer, header, block);
    return buffer;
}

}  // namespace navmap::ipc::gst
