// SPDX-License-Identifier: Apache-2.0
#pragma once
// FrameRing: a ring of frame slots in one memfd, written by the render thread and read by any
// number of local client processes through a per-slot sequence lock (docs/frame-protocol.md).
//
// The writer never waits: it bumps the slot's lock word to odd, copies, bumps it to even. A
// reader copies the slot and keeps the copy only if the lock word was even and unchanged around
// the copy and the slot still holds the sequence it was told about, so it never keeps a frame
// that was being overwritten (seqlock; Linux kernel `seqcount_t`, Wayland wl_shm for the fd).
//
// A client may also hold a frame in place instead of copying it (docs/frame-protocol.md "Holding
// a frame"): the server pins the slot from the notification until the client's ack, and the
// writer picks the least recently written slot that nobody pins. Only when every slot is pinned
// does it overwrite a pinned one (the oldest write), so a client that holds frames can never
// stop the stream; the holder sees the change of the slot's lock word when it releases.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>

#include "navmap/ipc/client/frame_format.h"
#include "navmap/ipc/client/frame_header.h"
#include "navmap/ipc/client/frame_view.h"
#include "navmap/ipc/net/result.h"
#include "navmap/ipc/net/unique_fd.h"

namespace navmap::ipc {

/// Geometry of a ring mapping; the server sends it in the handshake reply.
struct FrameRingLayout {
    std::uint32_t slots = 0;
    std::uint32_t width = 0;
    std::uint32_t height = 0;
    std::uint32_t stride = 0;
    PixelFormat format = PixelFormat::Rgba8;
    std::size_t slot_bytes = 0;   ///< distance between slots (page multiple)
    std::size_t total_bytes = 0;  ///< size of the memfd

    /// Byte offset of slot `i` (its lock word) from the start of the mapping.
    std::size_t slotOffset(std::uint32_t i) const noexcept;
    std::size_t pixelBytes() const noexcept { return static_cast<std::size_t>(stride) * height; }
    /// Computes slot_bytes/total_bytes for the given geometry.
    static FrameRingLayout make(std::uint32_t slots, std::uint32_t width, std::uint32_t height, PixelFormat format);
    /// Checks a layout received from a peer against the size of the mapped file.
    Status validate(std::size_t file_bytes) const;
};

/// Offsets inside a slot: lock word, then the FrameHeader, then the pixels.
inline constexpr std::size_t kRingHeaderBytes = 4096;  ///< ring header page: magic + latest sequence
inline constexpr std::size_t kSlotHeaderOffset = 64;
inline constexpr std::size_t kSlotPixelOffset = 256;
/// Ring header version: 2 since slots are chosen by the writer (a frame's slot is in its header
/// and found by its sequence), 1 had frame `seq` in slot (seq - 1) % slots.
inline constexpr std::uint32_t kRingVersion = 2;
/// Most slots a ring may have (FrameServerOptions::ring_slots, and what a client accepts).
inline constexpr std::uint32_t kMaxRingSlots = 64;

class FrameRing {
public:
    /// Creates the memfd, maps it writable for the render thread, then seals it against resizing
    /// and against any later write access (F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE |
    /// F_SEAL_SEAL; Linux >= 5.1): no descriptor of it, however re-opened, can write or map it
    /// writable. Setup-time: returns an Error naming memfd_create/ftruncate/mmap/fcntl on failure.
    static Result<std::unique_ptr<FrameRing>> create(const std::string& name, std::uint32_t slots, std::uint32_t width,
                                                     std::uint32_t height, PixelFormat format);
    ~FrameRing();
    FrameRing(const FrameRing&) = delete;
    FrameRing& operator=(const FrameRing&) = delete;

    /// Render thread: copies `frame` (RGBA8 or the ring's format, same width/height) into the
    /// least recently written slot that no client holds (the oldest write when all are held),
    /// converting the pixel format. Never blocks. Returns the new sequence (>= 1), or 0 when the
    /// frame does not fit this ring.
    std::uint64_t write(const FrameView& frame) noexcept;

    /// Render thread: the sequence the next write() will give its frame.
    std::uint64_t nextSequence() const noexcept { return m_next_sequence; }
    /// Server thread: pins the slot that holds frame `sequence` so that write() leaves it alone
    /// while another slot is free. Returns the slot, or -1 when that frame is gone (overwritten
    /// or being written). Every successful pin() needs one unpin(slot).
    int pin(std::uint64_t sequence) noexcept;
    void unpin(std::uint32_t slot) noexcept;
    /// Writes that had to take a pinned slot because every slot was pinned. Any thread.
    std::uint64_t pinnedOverwrites() const noexcept { return m_pinned_overwrites.load(std::memory_order_relaxed); }

    /// Newest complete sequence (0 before the first write). Any thread.
    std::uint64_t latestSequence() const noexcept;

    /// Copies frame `sequence` out of the ring into `pixels` (layout().pixelBytes() bytes, may be
    /// null to read only the header). False when that frame is gone or being overwritten. Any thread.
    bool read(std::uint64_t sequence, FrameHeader* header, std::uint8_t* pixels) const noexcept;

    const FrameRingLayout& layout() const noexcept { return m_layout; }
    /// Opens a new read-only descriptor of the memfd (for SCM_RIGHTS); the caller closes it.
    Result<int> openReadOnly() const;
    int fd() const noexcept { return m_fd.get(); }

    /// Reader side over any mapping (a client's read-only mmap): same contract as read().
    static bool readMapped(const std::uint8_t* base, const FrameRingLayout& layout, std::uint64_t sequence,
                           FrameHeader* header, std::uint8_t* pixels) noexcept;
    /// Newest sequence recorded in a mapped ring header.
    static std::uint64_t latestMapped(const std::uint8_t* base) noexcept;
    /// Checks the ring header of a mapping: magic "NMRG", kRingVersion and the layout's geometry.
    static Status checkMapped(const std::uint8_t* base, const FrameRingLayout& layout);
    /// Finds the slot holding frame `sequence` and returns it with its lock word (even) at that
    /// moment; -1 when the frame is gone or being written. A holder compares the lock word later
    /// (lockWord()) to learn whether the slot changed since.
    static int findSlot(const std::uint8_t* base, const FrameRingLayout& layout, std::uint64_t sequence,
                        std::uint64_t* lock) noexcept;
    static std::uint64_t lockWord(const std::uint8_t* base, const FrameRingLayout& layout, std::uint32_t slot) noexcept;

private:
    FrameRing(int fd, std::uint8_t* base, FrameRingLayout layout);

    net::UniqueFd m_fd;
    std::uint8_t* m_base = nullptr;
    FrameRingLayout m_layout;
    std::uint64_t m_next_sequence = 1;                     // render thread only
    std::uint32_t m_next_slot = 0;                         // render thread only: the least recently written slot
    std::unique_ptr<std::atomic<std::uint32_t>[]> m_pins;  // per slot: clients holding it (server memory)
    std::atomic<std::uint64_t> m_pinned_overwrites{0};
};

}  // namespace navmap::ipc
