// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/frame_ring.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>

#include "navmap/ipc/net/sys_error.h"

// glibc < 2.29 lacks the name; the value is the kernel's (include/uapi/linux/fcntl.h, Linux 5.1).
#ifndef F_SEAL_FUTURE_WRITE
#define F_SEAL_FUTURE_WRITE 0x0010
#endif

namespace navmap::ipc {
namespace {

constexpr std::uint32_t kRingMagic = 0x47524D4EU;  // "NMRG"
constexpr std::size_t kLatestOffset = 64;
constexpr std::size_t kPage = 4096;

std::size_t roundUp(std::size_t v, std::size_t a) { return (v + a - 1) / a * a; }

// The lock words live in shared memory that other processes map (read-only), so they are plain
// 8-byte words accessed with the compiler's atomic builtins (lock-free and address-free, as
// std::atomic<uint64_t> would be, but usable on a const mapping).
std::uint64_t loadAcquire(const std::uint8_t* p) noexcept {
    return __atomic_load_n(reinterpret_cast<const std::uint64_t*>(p), __ATOMIC_ACQUIRE);
}

std::int64_t realtimeNs() noexcept {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace

std::size_t FrameRingLayout::slotOffset(std::uint32_t i) const noexcept { return kRingHeaderBytes + slot_bytes * i; }

FrameRingLayout FrameRingLayout::make(std::uint32_t slots, std::uint32_t width, std::uint32_t height,
                                      PixelFormat format) {
    FrameRingLayout l;
    l.slots = slots;
    l.width = width;
    l.height = height;
    l.format = format;
    l.stride = width * static_cast<std::uint32_t>(bytesPerPixel(format));
    l.slot_bytes = roundUp(kSlotPixelOffset + l.pixelBytes(), kPage);
    l.total_bytes = kRingHeaderBytes + l.slot_bytes * slots;
    return l;
}

Status FrameRingLayout::validate(std::size_t file_bytes) const {
    if (slots < 1 || slots > kMaxRingSlots || width == 0 || height == 0 || width > kMaxFrameDimension ||
        height > kMaxFrameDimension || !isKnownPixelFormat(static_cast<std::uint32_t>(format))) {
        return Error{"ring layout: bad geometry"};
    }
    const FrameRingLayout expect = make(slots, width, height, format);
    if (stride != expect.stride || slot_bytes != expect.slot_bytes || total_bytes != expect.total_bytes) {
        return Error{"ring layout: sizes do not match the geometry"};
    }
    if (file_bytes < total_bytes) {
        return Error{"ring layout: shared memory has " + std::to_string(file_bytes) + " bytes, layout needs " +
                     std::to_string(total_bytes)};
    }
    return {};
}

Result<std::unique_ptr<FrameRing>> FrameRing::create(const std::string& name, std::uint32_t slots, std::uint32_t width,
                                                     std::uint32_t height, PixelFormat format) {
    if (slots < 2 || slots > kMaxRingSlots || width == 0 || height == 0 || width > kMaxFrameDimension ||
        height > kMaxFrameDimension || bytesPerPixel(format) == 0) {
        return Error{"FrameRing(" + name + "): bad geometry"};
    }
    const FrameRingLayout layout = FrameRingLayout::make(slots, width, height, format);
    net::UniqueFd fd(memfd_create(name.c_str(), MFD_CLOEXEC | MFD_ALLOW_SEALING));
    if (!fd.valid()) {
        return Error{net::sysError("memfd_create", name)};
    }
    if (ftruncate(fd.get(), static_cast<off_t>(layout.total_bytes)) != 0) {
        return Error{net::sysError("ftruncate", name)};
    }
    void* p = mmap(nullptr, layout.total_bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd.get(), 0);
    if (p == MAP_FAILED) {
        return Error{net::sysError("mmap", name)};
    }
    auto* base = static_cast<std::uint8_t*>(p);
    // Touch every page now (server thread) so the render thread's first writes do not fault.
    std::memset(base, 0, layout.total_bytes);
    const std::uint32_t hdr[] = {
        kRingMagic, kRingVersion, slots, width, height, layout.stride, static_cast<std::uint32_t>(format)};
    std::memcpy(base, hdr, sizeof(hdr));
    // Sealed after the writable mapping above exists: clients can rely on the size (no shrink or
    // grow), and nobody can make the memory writable any more, even a client that re-opens its
    // descriptor through /proc/self/fd read-write (F_SEAL_FUTURE_WRITE refuses write(), writable
    // shared mappings and hole punching; only mappings made before the seal keep writing).
    // F_SEAL_SEAL last, so the set is final.
    if (fcntl(fd.get(), F_ADD_SEALS, F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE | F_SEAL_SEAL) != 0) {
        const int e = errno;
        munmap(p, layout.total_bytes);
        return Error{net::sysError("fcntl", name + ", F_ADD_SEALS F_SEAL_FUTURE_WRITE", e) +
                     (e == EINVAL ? " (needs Linux >= 5.1)" : "")};
    }
    return std::unique_ptr<FrameRing>(new FrameRing(fd.release(), base, layout));
}

FrameRing::FrameRing(int fd, std::uint8_t* base, FrameRingLayout layout)
    : m_fd(fd), m_base(base), m_layout(layout), m_pins(new std::atomic<std::uint32_t>[layout.slots]) {
    for (std::uint32_t i = 0; i < layout.slots; ++i) {
        m_pins[i].store(0, std::memory_order_relaxed);
    }
}

FrameRing::~FrameRing() {
    if (m_base != nullptr) {
        munmap(m_base, m_layout.total_bytes);
    }
}

std::uint64_t FrameRing::write(const FrameView& frame) noexcept {
    if (frame.pixels == nullptr || frame.width != static_cast<int>(m_layout.width) ||
        frame.height != static_cast<int>(m_layout.height) ||
        (frame.format != PixelFormat::Rgba8 && frame.format != m_layout.format)) {
        return 0;
    }
    const std::uint64_t seq = m_next_sequence++;
    // The least recently written slot that no client holds. Claiming a slot and pinning one are
    // the two halves of Dekker's protocol: the writer makes the lock word odd, then reads the pin
    // count; pin() raises the count, then reads the lock word (each with a full fence between), so
    // at least one of them sees the other and steps back. A slot claimed and then found pinned is
    // given back unchanged (its old even lock word: readers see no change, and nothing changed).
    std::uint32_t slot = m_next_slot;
    std::uint64_t* lock = nullptr;
    std::uint64_t l = 0;
    for (std::uint32_t k = 0; k < m_layout.slots && lock == nullptr; ++k) {
        const std::uint32_t candidate = (m_next_slot + k) % m_layout.slots;
        if (m_pins[candidate].load(std::memory_order_relaxed) != 0) {
            continue;
        }
        auto* word = reinterpret_cast<std::uint64_t*>(m_base + m_layout.slotOffset(candidate));
        const std::uint64_t old = __atomic_load_n(word, __ATOMIC_RELAXED);
        __atomic_store_n(word, old + 1, __ATOMIC_RELAXED);
        __atomic_thread_fence(__ATOMIC_SEQ_CST);
        if (m_pins[candidate].load(std::memory_order_relaxed) != 0) {
            __atomic_store_n(word, old, __ATOMIC_RELEASE);  // pinned meanwhile: untouched, give it back
            continue;
        }
        slot = candidate;
        lock = word;
        l = old;
    }
    if (lock == nullptr) {
        // Every slot is held: the stream must not stop for its clients, so the oldest write goes
        // (its holder learns it from the lock word when it releases the frame).
        m_pinned_overwrites.fetch_add(1, std::memory_order_relaxed);
        lock = reinterpret_cast<std::uint64_t*>(m_base + m_layout.slotOffset(slot));
        l = __atomic_load_n(lock, __ATOMIC_RELAXED);
        __atomic_store_n(lock, l + 1, __ATOMIC_RELAXED);
        __atomic_thread_fence(__ATOMIC_RELEASE);
    }
    m_next_slot = (slot + 1) % m_layout.slots;
    std::uint8_t* s = m_base + m_layout.slotOffset(slot);
    // Sequence lock, writer side: odd while the slot changes, even (and larger) when done.

    FrameHeader h;
    h.kind = FrameKind::Frame;
    h.encoding = FrameEncoding::Shm;
    h.format = m_layout.format;
    h.sequence = seq;
    h.render_time_ns = frame.render_time_ns != 0 ? frame.render_time_ns : realtimeNs();
    h.source_time_ns = frame.source_time_ns;
    h.width = m_layout.width;
    h.height = m_layout.height;
    h.stride = m_layout.stride;
    h.slot = slot;
    h.validity = frame.validity;
    const auto bytes = encodeFrameHeader(h);
    std::memcpy(s + kSlotHeaderOffset, bytes.data(), bytes.size());

    const std::size_t src_stride = frame.stride > 0 ? static_cast<std::size_t>(frame.stride)
                                                    : static_cast<std::size_t>(frame.width) *
                                                          static_cast<std::size_t>(bytesPerPixel(frame.format));
    std::uint8_t* dst = s + kSlotPixelOffset;
    if (frame.format == m_layout.format && src_stride == m_layout.stride) {
        std::memcpy(dst, frame.pixels, m_layout.pixelBytes());
    } else {
        for (std::uint32_t y = 0; y < m_layout.height; ++y) {
            const std::uint8_t* src = frame.pixels + src_stride * y;
            if (frame.format == m_layout.format) {
                std::memcpy(dst + static_cast<std::size_t>(m_layout.stride) * y, src, m_layout.stride);
            } else {
                convertRowFromRgba(src, m_layout.format, dst + static_cast<std::size_t>(m_layout.stride) * y,
                                   static_cast<int>(m_layout.width));
            }
        }
    }
    __atomic_store_n(lock, l + 2, __ATOMIC_RELEASE);
    __atomic_store_n(reinterpret_cast<std::uint64_t*>(m_base + kLatestOffset), seq, __ATOMIC_RELEASE);
    return seq;
}

std::uint64_t FrameRing::latestSequence() const noexcept { return latestMapped(m_base); }

int FrameRing::pin(std::uint64_t sequence) noexcept {
    std::uint64_t lock = 0;
    const int slot = findSlot(m_base, m_layout, sequence, &lock);
    if (slot < 0) {
        return -1;
    }
    const auto i = static_cast<std::uint32_t>(slot);
    m_pins[i].fetch_add(1, std::memory_order_relaxed);
    __atomic_thread_fence(__ATOMIC_SEQ_CST);  // Dekker: the pin is visible before the lock word is read
    if (lockWord(m_base, m_layout, i) != lock) {
        m_pins[i].fetch_sub(1, std::memory_order_release);  // claimed by the writer meanwhile
        return -1;
    }
    return slot;
}

void FrameRing::unpin(std::uint32_t slot) noexcept {
    if (slot < m_layout.slots) {
        m_pins[slot].fetch_sub(1, std::memory_order_release);
    }
}

bool FrameRing::read(std::uint64_t sequence, FrameHeader* header, std::uint8_t* pixels) const noexcept {
    return readMapped(m_base, m_layout, sequence, header, pixels);
}

std::uint64_t FrameRing::latestMapped(const std::uint8_t* base) noexcept { return loadAcquire(base + kLatestOffset); }

std::uint64_t FrameRing::lockWord(const std::uint8_t* base, const FrameRingLayout& layout,
                                  std::uint32_t slot) noexcept {
    __atomic_thread_fence(__ATOMIC_ACQUIRE);
    return __atomic_load_n(reinterpret_cast<const std::uint64_t*>(base + layout.slotOffset(slot)), __ATOMIC_RELAXED);
}

int FrameRing::findSlot(const std::uint8_t* base, const FrameRingLayout& layout, std::uint64_t sequence,
                        std::uint64_t* lock) noexcept {
    if (sequence == 0) {
        return -1;
    }
    for (std::uint32_t i = 0; i < layout.slots; ++i) {
        const std::uint8_t* s = base + layout.slotOffset(i);
        const std::uint64_t before = loadAcquire(s);
        if (before == 0 || (before & 1U) != 0) {
            continue;
        }
        std::uint64_t seq = 0;
        std::memcpy(&seq, s + kSlotHeaderOffset + 16, sizeof(seq));  // little-endian host (x86-64, AArch64)
        __atomic_thread_fence(__ATOMIC_ACQUIRE);
        if (seq == sequence && __atomic_load_n(reinterpret_cast<const std::uint64_t*>(s), __ATOMIC_RELAXED) == before) {
            *lock = before;
            return static_cast<int>(i);
        }
    }
    return -1;
}

Status FrameRing::checkMapped(const std::uint8_t* base, const FrameRingLayout& layout) {
    std::uint32_t hdr[7] = {};
    std::memcpy(hdr, base, sizeof(hdr));
    if (hdr[0] != kRingMagic) {
        return Error{"ring header: no \"NMRG\" magic"};
    }
    if (hdr[1] != kRingVersion) {
        return Error{"ring header: version " + std::to_string(hdr[1]) + ", this client reads " +
                     std::to_string(kRingVersion)};
    }
    if (hdr[2] != layout.slots || hdr[3] != layout.width || hdr[4] != layout.height || hdr[5] != layout.stride ||
        hdr[6] != static_cast<std::uint32_t>(layout.format)) {
        return Error{"ring header: geometry differs from the handshake"};
    }
    return {};
}

bool FrameRing::readMapped(const std::uint8_t* base, const FrameRingLayout& layout, std::uint64_t sequence,
                           FrameHeader* header, std::uint8_t* pixels) noexcept {
    if (sequence == 0 || layout.slots == 0) {
        return false;
    }
    // The frame's slot, found by its sequence (the writer chooses slots, see write()).
    std::uint64_t before = 0;
    const int found = findSlot(base, layout, sequence, &before);
    if (found < 0) {
        return false;
    }
    const std::uint8_t* s = base + layout.slotOffset(static_cast<std::uint32_t>(found));
    // Sequence lock, reader side: keep the copy only if the lock word was even and unchanged.
    std::uint8_t hb[kFrameHeaderBytes];
    std::memcpy(hb, s + kSlotHeaderOffset, sizeof(hb));
    if (pixels != nullptr) {
        std::memcpy(pixels, s + kSlotPixelOffset, layout.pixelBytes());
    }
    __atomic_thread_fence(__ATOMIC_ACQUIRE);
    const std::uint64_t after = __atomic_load_n(reinterpret_cast<const std::uint64_t*>(s), __ATOMIC_RELAXED);
    if (after != before) {
        return false;
    }
    auto h = decodeFrameHeader(hb, sizeof(hb));
    if (!h.ok() || h.value().width != layout.width || h.value().height != layout.height ||
        h.value().stride != layout.stride) {
        return false;
    }
    if (header != nullptr) {
        *header = h.value();
    }
    return true;
}

Result<int> FrameRing::openReadOnly() const {
    const std::string proc = "/proc/self/fd/" + std::to_string(m_fd.get());
    const int fd = open(proc.c_str(), O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        return Error{net::sysError("open", proc + ", O_RDONLY")};
    }
    return fd;
}

}  // namespace navmap::ipc
