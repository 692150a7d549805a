// SPDX-License-Identifier: Apache-2.0
#include "shm_buffer_source.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>
#include <wayland-client.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace navmap::ipc::wayland {

struct ShmBufferSource::Buffer {
    wl_buffer* buffer = nullptr;
    void* map = MAP_FAILED;
    std::size_t bytes = 0;
    TargetPixels target;
    bool busy = false;  ///< attached and not released by the compositor yet

    ~Buffer() {
        if (buffer != nullptr) wl_buffer_destroy(buffer);
        if (map != MAP_FAILED) munmap(map, bytes);
    }
};

namespace {

std::uint32_t wlShmFormat(ShmFormat format) noexcept {
    switch (format) {
        case ShmFormat::Xbgr8888: return WL_SHM_FORMAT_XBGR8888;
        case ShmFormat::Rgb565: return WL_SHM_FORMAT_RGB565;
        case ShmFormat::Xrgb8888: break;
    }
    return WL_SHM_FORMAT_XRGB8888;
}

void onRelease(void* data, wl_buffer* /*buffer*/) { static_cast<ShmBufferSource::Buffer*>(data)->busy = false; }

const wl_buffer_listener kBufferListener = {onRelease};

}  // namespace

ShmBufferSource::ShmBufferSource(wl_shm* shm, std::vector<std::uint32_t> formats) : m_shm(shm) {
    const auto has = [&](std::uint32_t f) { return std::find(formats.begin(), formats.end(), f) != formats.end(); };
    m_has_xbgr8888 = has(WL_SHM_FORMAT_XBGR8888);
    m_has_rgb565 = has(WL_SHM_FORMAT_RGB565);
}

ShmBufferSource::~ShmBufferSource() = default;

ShmFormat ShmBufferSource::formatFor(PixelFormat stream) const noexcept {
    return chooseShmFormat(stream, m_has_xbgr8888, m_has_rgb565);
}

void ShmBufferSource::dropStale(int width, int height, ShmFormat format) {
    std::erase_if(m_buffers, [&](const std::unique_ptr<Buffer>& b) {
        const TargetPixels& t = b->target;
        return !b->busy && (t.width != width || t.height != height || t.format != format);
    });
}

ShmBufferSource::Buffer* ShmBufferSource::freeBuffer(int width, int height, ShmFormat format) {
    dropStale(width, height, format);
    int same_size = 0;
    for (auto& b : m_buffers) {
        const TargetPixels& t = b->target;
        if (t.width == width && t.height == height && t.format == format) {
            if (!b->busy) return b.get();
            ++same_size;
        }
    }
    if (same_size >= kMaxBuffers) {
        return nullptr;  // the compositor holds them all: skip this frame
    }
    auto b = std::make_unique<Buffer>();
    b->target.width = width;
    b->target.height = height;
    b->target.format = format;
    b->target.stride = static_cast<std::size_t>(width) * shmBytesPerPixel(format);
    b->bytes = b->target.stride * static_cast<std::size_t>(height);
    const int fd = memfd_create("navmap-wayland-buffer", MFD_CLOEXEC);
    if (fd < 0) {
        m_last_error = std::string("memfd_create(navmap-wayland-buffer): ") + std::strerror(errno);
        return nullptr;
    }
    if (ftruncate(fd, static_cast<off_t>(b->bytes)) != 0) {
        m_last_error = "ftruncate(navmap-wayland-buffer, " + std::to_string(b->bytes) + "): " + std::strerror(errno);
        close(fd);
        return nullptr;
    }
    b->map = mmap(nullptr, b->bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0);
    if (b->map == MAP_FAILED) {
        m_last_error = std::string("mmap(navmap-wayland-buffer): ") + std::strerror(errno);
        close(fd);
        return nullptr;
    }
    b->target.pixels = static_cast<std::uint8_t*>(b->map);
    wl_shm_pool* pool = wl_shm_create_pool(m_shm, fd, static_cast<std::int32_t>(b->bytes));
    b->buffer = wl_shm_pool_create_buffer(pool, 0, width, height, static_cast<std::int32_t>(b->target.stride),
                                          wlShmFormat(format));
    wl_shm_pool_destroy(pool);  // the buffer keeps the memory; the descriptor is the compositor's now
    close(fd);
    wl_buffer_add_listener(b->buffer, &kBufferListener, b.get());
    m_buffers.push_back(std::move(b));
    return m_buffers.back().get();
}

void ShmBufferSource::attachBuffer(wl_surface* surface, Buffer& b) {
    b.busy = true;
    wl_surface_attach(surface, b.buffer, 0, 0);
    wl_surface_damage(surface, 0, 0, b.target.width, b.target.height);  // buffer scale 1: the same
}

bool ShmBufferSource::attach(wl_surface* surface, const DisplayFrame& frame, int width, int height) {
    m_last_error.clear();
    Buffer* b = freeBuffer(width, height, formatFor(frame.pixels.format));
    if (b == nullptr) return false;
    m_placement = blitFrame(frame.pixels, b->target);
    attachBuffer(surface, *b);
    return true;
}

bool ShmBufferSource::attachBlank(wl_surface* surface, int width, int height) {
    m_last_error.clear();
    Buffer* b = freeBuffer(width, height, ShmFormat::Xrgb8888);
    if (b == nullptr) return false;
    clearTarget(b->target);
    attachBuffer(surface, *b);
    return true;
}

}  // namespace navmap::ipc::wayland
