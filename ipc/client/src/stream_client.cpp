// SPDX-License-Identifier: Apache-2.0
#include "navmap/ipc/client/stream_client.h"

#include <fcntl.h>
#include <poll.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <optional>

#include "navmap/ipc/client/frame_ring.h"
#include "navmap/ipc/client/stream_socket.h"
#include "navmap/ipc/net/recv_before.h"

namespace navmap::ipc {

using net::sysError;
using net::UniqueFd;
using Clock = std::chrono::steady_clock;

// glibc < 2.29 lacks the name; the value is the kernel's (include/uapi/linux/fcntl.h, Linux 5.1).
#ifndef F_SEAL_FUTURE_WRITE
#define F_SEAL_FUTURE_WRITE 0x0010
#endif

namespace {

Status sendAll(int fd, const char* data, std::size_t n, const std::string& peer) {
    while (n > 0) {
        const ssize_t w = ::send(fd, data, n, MSG_NOSIGNAL);
        if (w < 0) {
            if (errno == EINTR) {
                continue;
            }
            return Error{sysError("send", peer)};
        }
        data += w;
        n -= static_cast<std::size_t>(w);
    }
    return {};
}

// At most `max` bytes of a server's text for an error message, control bytes and non-ASCII as '?'.
std::string printable(const std::string& text, std::size_t max) {
    std::string out = text.substr(0, max);
    for (char& c : out) {
        if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7F) {
            c = '?';
        }
    }
    return out;
}

// The ring descriptor comes from a server the client does not trust: before it is mapped, it must
// be a memfd whose size nobody can change and whose pages nobody can write any more. A file or
// memfd that can shrink turns every later read of the mapping into a possible SIGBUS; one that
// can be written lets the server change a frame the client holds. F_GET_SEALS fails (EINVAL) on
// anything but a memfd (or another shmem file, whose seals are then just F_SEAL_SEAL).
Status checkRingDescriptor(int fd, const FrameRingLayout& layout, const std::string& peer) {
    const std::string what = "handshake with " + peer + ": ring descriptor ";
    struct stat st {};
    if (::fstat(fd, &st) != 0) {
        return Error{sysError("fstat", peer + " ring")};
    }
    if (!S_ISREG(st.st_mode)) {
        return Error{what + "is not a memfd (not even a regular file)"};
    }
    const int seals = ::fcntl(fd, F_GET_SEALS);
    if (seals < 0) {
        return Error{what + "is not a memfd (" + sysError("fcntl", "F_GET_SEALS") + ")"};
    }
    const bool sized = (seals & F_SEAL_SHRINK) != 0 && (seals & F_SEAL_GROW) != 0;
    const bool read_only = (seals & (F_SEAL_WRITE | F_SEAL_FUTURE_WRITE)) != 0;
    if (!sized || !read_only) {
        char have[16];
        std::snprintf(have, sizeof(have), "0x%x", static_cast<unsigned>(seals));
        return Error{what + "is not sealed: seals " + have +
                     ", need F_SEAL_SHRINK, F_SEAL_GROW and F_SEAL_WRITE or F_SEAL_FUTURE_WRITE"};
    }
    // Sealed against shrinking: the size checked now is the size for as long as it is mapped.
    if (auto s = layout.validate(static_cast<std::size_t>(st.st_size)); !s) {
        return Error{"handshake with " + peer + ": " + s.message()};
    }
    return {};
}

}  // namespace

Result<std::unique_ptr<StreamClient>> StreamClient::connectUnix(const std::string& path, const StreamRequest& request,
                                                                std::chrono::milliseconds timeout,
                                                                FrameInflater inflate) {
    if (request.payload == StreamPayload::Zlib && !inflate) {
        return Error{"connect(" + path + "): payload zlib needs a FrameInflater (the client library links no zlib)"};
    }
    auto fd = stream_detail::connectUnixSocket(path);
    if (!fd) {
        return fd.error();
    }
    if (request.payload != StreamPayload::Dmabuf || !request.dmabuf_fallback_shm) {
        return handshake(fd.value(), path, request, timeout, std::move(inflate));
    }
    auto dmabuf = handshake(fd.value(), path, request, timeout, inflate);
    if (dmabuf) {
        return dmabuf;
    }
    StreamRequest shm = request;
    shm.payload = StreamPayload::Shm;
    auto again = connectUnix(path, shm, timeout, std::move(inflate));
    if (again) {
        again.value()->m_fallback_reason = dmabuf.error().message;
    }
    return again;
}

Result<std::unique_ptr<StreamClient>> StreamClient::connectTcp(const std::string& host, int port,
                                                               const StreamRequest& request,
                                                               std::chrono::milliseconds timeout,
                                                               FrameInflater inflate) {
    const std::string peer = host + ":" + std::to_string(port);
    if (request.payload == StreamPayload::Shm || request.payload == StreamPayload::Dmabuf) {
        return Error{"connect(" + peer + "): payload " + streamPayloadName(request.payload) + " needs the Unix socket"};
    }
    if (request.payload == StreamPayload::Zlib && !inflate) {
        return Error{"connect(" + peer + "): payload zlib needs a FrameInflater (the client library links no zlib)"};
    }
    auto fd = stream_detail::connectTcpSocket(host, port, timeout);
    if (!fd) {
        return fd.error();
    }
    return handshake(fd.value(), peer, request, timeout, std::move(inflate));
}

Result<std::unique_ptr<StreamClient>> StreamClient::handshake(int raw_fd, const std::string& peer,
                                                              const StreamRequest& request,
                                                              std::chrono::milliseconds timeout,
                                                              FrameInflater inflate) {
    UniqueFd fd(raw_fd);
    const auto deadline = Clock::now() + timeout;
    const std::string line = formatStreamRequest(request);
    // A server that refuses this peer (not allowed, too many clients) answers and closes at once,
    // possibly before the request is out: then the send fails, but the answer is waiting to be read.
    const Status sent = sendAll(fd.get(), line.data(), line.size(), peer);
    // Read the reply line; the ring's memfd (shm) arrives with its first bytes (SCM_RIGHTS).
    std::string reply;
    std::vector<UniqueFd> fds;  // the ring's memfd (shm); a first dma-buf frame's fds may come early
    std::vector<std::uint8_t> rest;
    for (;;) {
        pollfd p{fd.get(), POLLIN, 0};
        const int n = ::poll(&p, 1, stream_detail::msLeft(deadline));
        if (n == 0) {
            return Error{"handshake with " + peer + ": no reply within " + std::to_string(timeout.count()) + " ms"};
        }
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            return Error{sysError("poll", peer)};
        }
        char buf[8192];
        iovec iov{buf, sizeof(buf)};
        alignas(cmsghdr) char control[CMSG_SPACE(sizeof(int) * 4)] = {};
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof(control);
        const ssize_t r = ::recvmsg(fd.get(), &msg, MSG_CMSG_CLOEXEC);
        if (r < 0) {
            if (errno == EINTR) {
                continue;
            }
            return Error{sent.ok() ? sysError("recvmsg", peer) : sent.message()};
        }
        for (cmsghdr* cm = CMSG_FIRSTHDR(&msg); cm != nullptr; cm = CMSG_NXTHDR(&msg, cm)) {
            if (cm->cmsg_level == SOL_SOCKET && cm->cmsg_type == SCM_RIGHTS) {
                const std::size_t count = (cm->cmsg_len - CMSG_LEN(0)) / sizeof(int);
                for (std::size_t i = 0; i < count; ++i) {
                    int f = -1;
                    std::memcpy(&f, CMSG_DATA(cm) + i * sizeof(int), sizeof(int));
                    fds.emplace_back(f);
                }
            }
        }
        if (r == 0) {
            if (!sent.ok() && reply.empty()) {
                return Error{sent.message()};
            }
            return Error{"handshake with " + peer + ": connection closed" +
                         (reply.empty() ? "" : " after '" + printable(reply, 200) + "'")};
        }
        reply.append(buf, static_cast<std::size_t>(r));
        const auto nl = reply.find('\n');
        if (nl != std::string::npos) {
            rest.assign(reply.begin() + static_cast<std::ptrdiff_t>(nl) + 1, reply.end());
            reply.resize(nl);
            break;
        }
        if (reply.size() > kMaxHandshakeBytes) {
            return Error{"handshake with " + peer + ": reply longer than " + std::to_string(kMaxHandshakeBytes) +
                         " bytes"};
        }
    }
    auto parsed = parseStreamReply(reply, request);
    if (!parsed) {
        return Error{"handshake with " + peer + ": " + parsed.error().message + " in '" + printable(reply, 200) + "'"};
    }
    const StreamReply& answer = parsed.value();
    if (!answer.accepted) {
        return Error{"handshake refused by " + peer + ": " + printable(answer.refusal, 1024)};
    }
    if (!sent.ok()) {
        return Error{sent.message()};
    }
    auto client = std::unique_ptr<StreamClient>(new StreamClient());
    client->m_peer = peer;
    client->m_payload = request.payload;
    client->m_profile = answer.profile;
    client->m_in = std::move(rest);
    client->m_inflate = std::move(inflate);
    client->m_hold = request.hold;
    client->m_meta = request.meta;
    if (request.payload == StreamPayload::Dmabuf) {
        // Descriptors that came with the reply's read belong to the first frame's bytes in `rest`.
        for (auto& f : fds) client->m_fds.push_back(f.release());
    }
    if (request.payload == StreamPayload::Shm) {
        // The memfd; any other descriptor is unexpected and closed with `fds`.
        UniqueFd memfd = fds.empty() ? UniqueFd() : std::move(fds.front());
        if (!memfd.valid()) {
            return Error{"handshake with " + peer + ": no shared-memory descriptor in the reply"};
        }
        const FrameRingLayout l =
            FrameRingLayout::make(answer.ring_slots, static_cast<std::uint32_t>(answer.profile.width),
                                  static_cast<std::uint32_t>(answer.profile.height), answer.profile.format);
        if (auto s = checkRingDescriptor(memfd.get(), l, peer); !s) {
            return Error{s.message()};
        }
        void* p = ::mmap(nullptr, l.total_bytes, PROT_READ, MAP_SHARED, memfd.get(), 0);
        if (p == MAP_FAILED) {
            return Error{sysError("mmap", peer + " ring")};
        }
        client->m_map = static_cast<const std::uint8_t*>(p);
        client->m_map_bytes = l.total_bytes;
        client->m_slots = l.slots;
        if (auto s = FrameRing::checkMapped(client->m_map, l); !s) {
            return Error{"handshake with " + peer + ": " + s.message()};  // the destructor unmaps
        }
    }
    client->m_fd = fd.release();
    return client;
}

StreamClient::~StreamClient() {
    if (m_map != nullptr) {
        ::munmap(const_cast<std::uint8_t*>(m_map), m_map_bytes);
    }
    for (const int f : m_fds) ::close(f);
    for (int i = 0; i < kDmabufMaxBuffers; ++i) unmapDmabuf(i);
    for (const int f : m_dmabufs) {
        if (f >= 0) ::close(f);
    }
    // The installed header keeps a plain int (ipc/net is not part of the client's API).
    const UniqueFd owned(m_fd);
}

Status StreamClient::readExact(std::uint8_t* dst, std::size_t n, Clock::time_point deadline, bool* timed_out) {
    *timed_out = false;
    const std::size_t buffered = std::min(n, m_in.size() - m_in_pos);
    if (buffered > 0) {
        std::memcpy(dst, m_in.data() + m_in_pos, buffered);
        m_in_pos += buffered;
        dst += buffered;
        n -= buffered;
        if (m_in_pos == m_in.size()) {
            m_in.clear();
            m_in_pos = 0;
        }
    }
    while (n > 0) {
        const auto got = net::recvBefore(m_fd, dst, n, deadline, m_peer, fdSink());
        if (got.kind == net::Received::Kind::TimedOut) {
            *timed_out = true;
            return Error{"timeout"};
        }
        if (got.kind == net::Received::Kind::Failed) {
            return Error{got.error};
        }
        dst += got.bytes;
        n -= got.bytes;
    }
    return {};
}

Result<bool> StreamClient::readHeader(FrameHeader& out, Clock::time_point deadline) {
    // A header may arrive in pieces across calls; keep what we have. Byte-wise progress is
    // tracked, so a timeout never loses a partial header.
    if (m_header_have < kFrameHeaderBytes) {
        const std::size_t want = kFrameHeaderBytes - m_header_have;
        const std::size_t buffered = std::min(want, m_in.size() - m_in_pos);
        if (buffered > 0) {  // m_in may be empty: no memcpy from its null data()
            std::memcpy(m_header_buf + m_header_have, m_in.data() + m_in_pos, buffered);
        }
        m_in_pos += buffered;
        m_header_have += buffered;
        if (m_in_pos == m_in.size()) {
            m_in.clear();
            m_in_pos = 0;
        }
        while (m_header_have < kFrameHeaderBytes) {
            const auto got = net::recvBefore(m_fd, m_header_buf + m_header_have, kFrameHeaderBytes - m_header_have,
                                             deadline, m_peer, fdSink());
            if (got.kind == net::Received::Kind::TimedOut) {
                return false;
            }
            if (got.kind == net::Received::Kind::Failed) {
                return Error{got.error};
            }
            m_header_have += got.bytes;
        }
    }
    auto decoded = decodeFrameHeader(m_header_buf, kFrameHeaderBytes);
    m_header_have = 0;
    if (!decoded) {
        return Error{m_peer + ": " + decoded.error().message};
    }
    out = decoded.value();
    return true;
}

Status StreamClient::readMeta(const FrameHeader& h, Clock::time_point deadline, std::optional<FrameMeta>* out) {
    out->reset();
    if (h.meta_bytes == 0) {
        return {};
    }
    if (!m_meta) {
        return Error{m_peer + ": frame " + std::to_string(h.sequence) + ": metadata block without asking for it"};
    }
    std::array<std::uint8_t, kMaxFrameMetaBytes> block{};
    bool timed_out = false;
    if (auto s = readExact(block.data(), h.meta_bytes, deadline, &timed_out); !s) {
        return s;
    }
    auto decoded = decodeFrameMeta(block.data(), h.meta_bytes);
    if (!decoded) {
        return Error{m_peer + ": frame " + std::to_string(h.sequence) + ": " + decoded.error().message};
    }
    *out = std::move(decoded.value());
    return {};
}

Result<bool> StreamClient::next(ReceivedFrame& out, std::chrono::milliseconds timeout) {
    return receive({&out, nullptr, nullptr}, timeout);
}

Result<bool> StreamClient::nextHeld(HeldFrame& out, std::chrono::milliseconds timeout) {
    if (!m_hold || (m_payload != StreamPayload::Shm && m_payload != StreamPayload::Dmabuf)) {
        return Error{m_peer + ": nextHeld() needs a stream opened with request.hold (payload shm or dmabuf)"};
    }
    return receive({nullptr, &out, nullptr}, timeout);
}

Status StreamClient::sendAck() {
    const char ack = 'A';
    return sendAll(m_fd, &ack, 1, m_peer);
}

Result<bool> StreamClient::release() {
    if (m_held < 0) {
        return true;
    }
    if (m_payload == StreamPayload::Dmabuf) {
        if (m_dmabuf_maps[static_cast<std::size_t>(m_held)].at != nullptr)
            stream_detail::dmaBufSync(m_dmabufs[m_held], false);
        m_held = -1;  // the server keeps the buffer from the renderer until this ack
        if (auto s = sendAck(); !s) {
            return Error{s.message()};
        }
        return true;
    }
    // The slot's lock word tells whether the server had to overwrite it while it was held.
    const bool intact =
        FrameRing::lockWord(m_map,
                            FrameRingLayout::make(m_slots, static_cast<std::uint32_t>(m_profile.width),
                                                  static_cast<std::uint32_t>(m_profile.height), m_profile.format),
                            static_cast<std::uint32_t>(m_held)) == m_held_lock;
    m_held = -1;
    if (!intact) {
        ++m_stats.held_overwritten;
    }
    const char ack = 'A';
    if (auto s = sendAll(m_fd, &ack, 1, m_peer); !s) {
        return Error{s.message()};
    }
    return intact;
}

Status StreamClient::takeStatus(const FrameHeader& h, Clock::time_point deadline) {
    // Before the first frame: what the server is doing about it. Not a frame; the caller waits on.
    std::string text(h.payload_bytes, '\0');
    bool timed_out = false;
    if (auto s = readExact(reinterpret_cast<std::uint8_t*>(text.data()), text.size(), deadline, &timed_out); !s) {
        return s;
    }
    if (auto s =
            validateTextPayload(FrameKind::Status, reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
        !s) {
        return Error{m_peer + ": " + s.message()};
    }
    ++m_stats.statuses;
    m_last_status = std::move(text);
    if (m_on_status) {
        m_on_status(m_last_status);
    }
    return {};
}

Result<bool> StreamClient::takeShm(FrameHeader& h, Out out, std::optional<FrameMeta>& meta,
                                   const std::uint8_t** held_pixels) {
    const FrameRingLayout l = FrameRingLayout::make(m_slots, h.width, h.height, h.format);
    FrameHeader slot_header;
    bool ok = false;
    if (out.held != nullptr) {
        // In place: the server pinned the frame's slot for us until our ack.
        std::uint64_t lock = 0;
        const int slot = FrameRing::findSlot(m_map, l, h.sequence, &lock);
        ok = slot >= 0 && FrameRing::readMapped(m_map, l, h.sequence, &slot_header, nullptr);
        if (ok) {
            m_held = slot;
            m_held_lock = lock;
            *held_pixels = m_map + l.slotOffset(static_cast<std::uint32_t>(slot)) + kSlotPixelOffset;
        }
    } else {
        out.copy->pixels.resize(h.pixelBytes());
        ok = FrameRing::readMapped(m_map, l, h.sequence, &slot_header, out.copy->pixels.data());
        if (!ok) {
            // Overwritten while the notification waited in the socket: the newest frame is
            // in the ring too, and the newest frame is what we want anyway.
            const std::uint64_t latest = FrameRing::latestMapped(m_map);
            if (latest > h.sequence && FrameRing::readMapped(m_map, l, latest, &slot_header, out.copy->pixels.data())) {
                h.sequence = latest;
                meta.reset();  // the block was the notified frame's, not this one's
                ok = true;
            }
        }
        if (ok) ++m_stats.cpu_copies;
    }
    if (!ok || out.held == nullptr) {
        // A copy is done (or there is nothing to hold): give the credit back right away,
        // so the server may notify the next frame while we work.
        if (auto s = sendAck(); !s) {
            return Error{s.message()};
        }
    }
    if (!ok) {
        ++m_stats.lost_locally;  // overwritten before we looked at it; wait for the next one
        return false;
    }
    h.render_time_ns = slot_header.render_time_ns;
    h.source_time_ns = slot_header.source_time_ns;
    h.slot = slot_header.slot;
    h.validity = slot_header.validity;
    return true;
}

Result<bool> StreamClient::receive(Out out, std::chrono::milliseconds timeout) {
    if (auto r = release(); !r) {
        return Error{r.error().message};
    }
    const auto deadline = Clock::now() + timeout;
    for (;;) {
        FrameHeader h;
        auto got = readHeader(h, deadline);
        if (!got) {
            return Error{got.error().message};
        }
        if (!got.value()) {
            return false;
        }
        // Payloads are read to the end even past the deadline: the stream must stay in step.
        const auto payload_deadline = std::max(deadline, Clock::now() + std::chrono::seconds(5));
        bool timed_out = false;
        if (h.kind == FrameKind::Error) {
            std::string message(h.payload_bytes, '\0');
            if (auto s = readExact(reinterpret_cast<std::uint8_t*>(message.data()), message.size(), payload_deadline,
                                   &timed_out);
                !s) {
                message = "(message lost: " + s.message() + ")";
            }
            return Error{"server " + m_peer + " closed the stream: " + message};
        }
        if (h.kind == FrameKind::Status) {
            if (auto s = takeStatus(h, payload_deadline); !s) {
                return Error{s.message()};
            }
            if (Clock::now() >= deadline) {
                return false;
            }
            continue;
        }
        const FrameEncoding want = m_payload == StreamPayload::Shm      ? FrameEncoding::Shm
                                   : m_payload == StreamPayload::Dmabuf ? FrameEncoding::Dmabuf
                                                                        : h.encoding;
        const bool socket_payload = want != FrameEncoding::Shm && want != FrameEncoding::Dmabuf;
        // The stride too: a display reads stride x height bytes at the pixels it is handed.
        if (h.encoding != want ||
            (socket_payload && h.encoding != FrameEncoding::Raw && h.encoding != FrameEncoding::Zlib) ||
            h.width != static_cast<std::uint32_t>(m_profile.width) ||
            h.height != static_cast<std::uint32_t>(m_profile.height) || h.format != m_profile.format ||
            h.stride != h.width * static_cast<std::uint32_t>(bytesPerPixel(h.format))) {
            return Error{m_peer + ": frame header does not match the negotiated profile"};
        }
        std::optional<FrameMeta> meta;
        if (auto s = readMeta(h, payload_deadline, &meta); !s) {
            return Error{s.message()};
        }
        const std::int64_t received_ns = stream_detail::realtimeNowNs();
        const std::uint8_t* held_pixels = nullptr;
        if (h.encoding == FrameEncoding::Shm) {
            auto taken = takeShm(h, out, meta, &held_pixels);
            if (!taken) {
                return Error{taken.error().message};
            }
            if (!taken.value()) {
                if (Clock::now() >= deadline) {
                    return false;
                }
                continue;
            }
            if (h.sequence <= m_last_sequence) {
                // Already handed out: we jumped ahead to the newest slot when an earlier
                // notification had been overwritten, and this one announces that same frame.
                if (auto r = release(); !r) {
                    return Error{r.error().message};
                }
                if (Clock::now() >= deadline) {
                    return false;
                }
                continue;
            }
        } else if (h.encoding == FrameEncoding::Dmabuf) {
            if (auto s = takeDmabuf(h, out, payload_deadline); !s) {
                return Error{s.message()};
            }
        } else if (h.encoding == FrameEncoding::Raw) {
            out.copy->pixels.resize(h.pixelBytes());
            if (auto s = readExact(out.copy->pixels.data(), out.copy->pixels.size(), payload_deadline, &timed_out);
                !s) {
                return Error{s.message()};
            }
        } else {
            out.copy->pixels.resize(h.pixelBytes());
            m_compressed.resize(h.payload_bytes);
            if (auto s = readExact(m_compressed.data(), m_compressed.size(), payload_deadline, &timed_out); !s) {
                return Error{s.message()};
            }
            if (!m_inflate || !m_inflate(m_compressed.data(), m_compressed.size(), out.copy->pixels.data(),
                                         out.copy->pixels.size())) {
                return Error{m_peer + ": frame " + std::to_string(h.sequence) + ": zlib payload does not inflate to " +
                             std::to_string(out.copy->pixels.size()) + " bytes"};
            }
        }
        m_last_sequence = h.sequence;
        m_stats.bytes += h.payload_bytes;
        m_stats.server_dropped = h.dropped;
        ++m_stats.frames;
        h.dropped += m_stats.lost_locally;
        if (out.held != nullptr) {
            if (h.encoding == FrameEncoding::Dmabuf) {
                h.stride = out.held->dmabuf.stride;  // the rows as they lie in the mapped buffer
                held_pixels = out.held->pixels;
            } else {
                out.held->dmabuf_fd = -1;
            }
            out.held->header = h;
            out.held->pixels = held_pixels;
            out.held->receive_time_ns = received_ns;
            out.held->meta = std::move(meta);
        } else if (out.dmabuf != nullptr) {
            out.dmabuf->header = h;
            out.dmabuf->receive_time_ns = received_ns;
            out.dmabuf->meta = std::move(meta);
        } else {
            out.copy->meta = std::move(meta);
            out.copy->header = h;
            out.copy->receive_time_ns = stream_detail::realtimeNowNs();
        }
        return true;
    }
}

}  // namespace navmap::ipc
