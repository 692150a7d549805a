// SPDX-License-Identifier: Apache-2.0
#include "readback.h"

#include <algorithm>
#include <cstring>

#include "gl/gl_work.h"
#include "navmap/common/check.h"

namespace navmap::render::gl {

namespace {

// GL rows run bottom-up; images are top-down.
void copyFlipped(const std::uint8_t* src, Image& dst) {
    const std::size_t stride = static_cast<std::size_t>(dst.width) * 4;
    for (int y = 0; y < dst.height; ++y) {
        std::memcpy(&dst.rgba[static_cast<std::size_t>(dst.height - 1 - y) * stride],
                    src + static_cast<std::size_t>(y) * stride, stride);
    }
}

// Swaps rows in place (bottom-up <-> top-down), so a read needs no second full-size buffer.
void flipRows(Image& image) {
    const std::size_t stride = static_cast<std::size_t>(image.width) * 4;
    std::vector<std::uint8_t> row(stride);
    for (int y = 0, z = image.height - 1; y < z; ++y, --z) {
        std::uint8_t* a = &image.rgba[static_cast<std::size_t>(y) * stride];
        std::uint8_t* b = &image.rgba[static_cast<std::size_t>(z) * stride];
        std::memcpy(row.data(), a, stride);
        std::memcpy(a, b, stride);
        std::memcpy(b, row.data(), stride);
    }
}

}  // namespace

Image readPixelsSync(int width, int height) {
    Image image(width, height);
    NAVMAP_CHECK(image.rgba.size() == static_cast<std::size_t>(width) * height * 4,
                 "readback image smaller than the frame");
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, width, height, GL_RGBA, GL_UNSIGNED_BYTE, image.rgba.data());
    flipRows(image);
    return image;
}

ReadbackRing::ReadbackRing(int width, int height, int slots)
    : m_width(width), m_height(height), m_pending(static_cast<std::size_t>(std::max(slots, 1))) {
    m_slots.resize(m_pending.slots());
    m_direct = m_slots.size() == 1;
    if (m_direct) return;  // submit() reads straight into the frame's image
    const auto bytes = static_cast<GLsizeiptr>(width) * height * 4;
    for (auto& slot : m_slots) {
        glGenBuffers(1, &slot.pbo);
        glBindBuffer(GL_PIXEL_PACK_BUFFER, slot.pbo);
        countedBufferData(GL_PIXEL_PACK_BUFFER, bytes, nullptr, GL_STREAM_READ);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
}

ReadbackRing::~ReadbackRing() {
    for (auto& slot : m_slots) {
        if (slot.fence) glDeleteSync(slot.fence);
        if (slot.pbo) glDeleteBuffers(1, &slot.pbo);
    }
}

std::optional<Frame> ReadbackRing::submit(std::uint64_t sequence) {
    if (m_direct) {
        Frame frame;
        frame.sequence = sequence;
        frame.image = readPixelsSync(m_width, m_height);  // waits for the frame's rendering
        m_read.push_back(std::move(frame));
        return std::nullopt;
    }
    // A full ring completes its oldest copy first: that slot is the one m_next names.
    return m_pending.submit([this](std::size_t i) { return complete(m_slots[i]); },
                            [this, sequence] { return startCopy(sequence); });
}

std::size_t ReadbackRing::startCopy(std::uint64_t sequence) {
    const std::size_t i = m_next;
    Slot& slot = m_slots[i];
    glBindBuffer(GL_PIXEL_PACK_BUFFER, slot.pbo);
    glPixelStorei(GL_PACK_ALIGNMENT, 1);
    glReadPixels(0, 0, m_width, m_height, GL_RGBA, GL_UNSIGNED_BYTE, nullptr);
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    slot.fence = glFenceSync(GL_SYNC_GPU_COMMANDS_COMPLETE, 0);
    slot.sequence = sequence;
    glFlush();  // start the copy now rather than at the next submit
    m_next = (m_next + 1) % m_slots.size();
    return i;
}

std::vector<Frame> ReadbackRing::drain() {
    std::vector<Frame> frames(std::make_move_iterator(m_read.begin()), std::make_move_iterator(m_read.end()));
    m_read.clear();
    for (auto& frame : m_pending.drain([this](std::size_t i) { return complete(m_slots[i]); })) {
        frames.push_back(std::move(frame));
    }
    return frames;
}

std::vector<Frame> ReadbackRing::collectReady() {
    std::vector<Frame> frames(std::make_move_iterator(m_read.begin()), std::make_move_iterator(m_read.end()));
    m_read.clear();
    const auto copied = [this](std::size_t i) {
        const Slot& slot = m_slots[i];
        if (!slot.fence) return true;
        const GLenum r = glClientWaitSync(slot.fence, GL_SYNC_FLUSH_COMMANDS_BIT, 0);
        return r == GL_ALREADY_SIGNALED || r == GL_CONDITION_SATISFIED;
    };
    for (auto& frame : m_pending.collect(copied, [this](std::size_t i) { return complete(m_slots[i]); })) {
        frames.push_back(std::move(frame));
    }
    return frames;
}

Frame ReadbackRing::complete(Slot& slot) {
    if (slot.fence) {
        // Normally already signalled: the copy was queued ring-1 frames ago.
        glClientWaitSync(slot.fence, GL_SYNC_FLUSH_COMMANDS_BIT, GL_TIMEOUT_IGNORED);
        glDeleteSync(slot.fence);
        slot.fence = nullptr;
    }
    Frame frame;
    frame.sequence = slot.sequence;
    frame.image = Image(m_width, m_height);
    const auto bytes = static_cast<GLsizeiptr>(m_width) * m_height * 4;
    NAVMAP_CHECK(frame.image.rgba.size() == static_cast<std::size_t>(bytes),
                 "readback image size differs from the PBO's");
    glBindBuffer(GL_PIXEL_PACK_BUFFER, slot.pbo);
    const void* mapped = glMapBufferRange(GL_PIXEL_PACK_BUFFER, 0, bytes, GL_MAP_READ_BIT);
    if (mapped) {
        copyFlipped(static_cast<const std::uint8_t*>(mapped), frame.image);
        glUnmapBuffer(GL_PIXEL_PACK_BUFFER);
    }
    glBindBuffer(GL_PIXEL_PACK_BUFFER, 0);
    return frame;
}

}  // namespace navmap::render::gl
