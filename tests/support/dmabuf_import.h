// SPDX-License-Identifier: Apache-2.0
#pragma once
// What a display process does with a dma-buf frame (docs/frame-protocol.md "dma-buf frames"):
// imports the buffer into its own EGL display as an EGLImage (EGL_EXT_image_dma_buf_import),
// binds it as a texture and draws from it. Here it is read back through a framebuffer, so a test
// can compare what a GPU client sees with the frame sent.
#include <string>

#include "navmap/render/image.h"

namespace navmap::test {

/// The buffer's layout as the dma-buf block gives it.
struct DmabufLayout {
    int fd = -1;
    unsigned fourcc = 0;
    unsigned long long modifier = 0;
    unsigned stride = 0, offset = 0;
    int width = 0, height = 0;
};

/// Imports `buffer` into a new surfaceless EGL display and context of this process and reads
/// it back, rows in the buffer's order (top first). False with `*error` naming the step that
/// failed ("no EGL_EXT_image_dma_buf_import", "eglCreateImageKHR: EGL_BAD_MATCH").
bool readThroughEgl(const DmabufLayout& buffer, render::Image* out, std::string* error);

}  // namespace navmap::test
