// SPDX-License-Identifier: Apache-2.0
#include "stream_rings.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <iomanip>
#include <sstream>
#include <utility>

#include "stream_stats.h"

namespace navmap::ipc::stream_detail {

namespace {

std::string describe(const std::string& view, int w, int h) {
    return view + " " + std::to_string(w) + "x" + std::to_string(h);
}

std::string sizeText(std::size_t b) {
    std::ostringstream os;
    os << std::fixed << std::setprecision(1);
    if (b < (std::size_t{1} << 20)) {
        os << static_cast<double>(b) / 1024 << " KiB";
    } else {
        os << static_cast<double>(b) / (1 << 20) << " MiB";
    }
    return os.str();
}

}  // namespace

void FrameMetaHistory::put(std::uint64_t sequence, Block block) {
    Block old;  // freed outside the lock
    {
        std::lock_guard lock(m_mutex);
        auto& slot = m_blocks[sequence % kFrames];
        old = std::move(slot.second);
        slot = {sequence, std::move(block)};
    }
}

FrameMetaHistory::Block FrameMetaHistory::get(std::uint64_t sequence) const {
    std::lock_guard lock(m_mutex);
    const auto& slot = m_blocks[sequence % kFrames];
    return slot.first == sequence ? slot.second : Block{};
}

int effectiveFps(int fps) { return fps == 0 ? kMaxStreamFps : fps; }

bool RingEntry::fillRaw(std::uint64_t seq) {
    if (raw_seq == seq) {
        return true;
    }
    raw.resize(ring->layout().pixelBytes());
    if (!ring->read(seq, &raw_header, raw.data())) {
        return false;
    }
    raw_seq = seq;
    return true;
}

RingSet::RingSet(const FrameServerOptions& options, StreamStats& stats) : m_options(options), m_stats(stats) {}

Result<std::string> RingSet::refuseNotRendered(std::string message) {
    m_stats.count(&FrameServerStats::refused_not_rendered);
    return Error{std::move(message)};
}

Result<std::string> RingSet::resolve(const StreamProfile& profile) {
    const auto& rendered = m_options.rendered_profiles;
    if (rendered.empty()) {
        return profile.view;
    }
    // By name first: two profiles may share a view and size and differ in style (glowing roads).
    for (const auto& r : rendered) {
        if (r.name == profile.name) {
            if (r.view == profile.view && r.width == profile.width && r.height == profile.height) {
                return r.name;
            }
            return refuseNotRendered("profile " + r.name + " is rendered as " + describe(r.view, r.width, r.height) +
                                     ", not " + describe(profile.view, profile.width, profile.height));
        }
    }
    // Another name: the first rendered profile of that view and size.
    for (const auto& r : rendered) {
        if (r.view == profile.view && r.width == profile.width && r.height == profile.height) {
            return r.name;
        }
    }
    std::string list;
    for (const auto& r : rendered) {
        list += (list.empty() ? "" : ", ") + r.name + " (" + describe(r.view, r.width, r.height) + ")";
    }
    return refuseNotRendered(describe(profile.view, profile.width, profile.height) +
                             " is not rendered here; rendered: " + list);
}

std::shared_ptr<RingEntry> RingSet::find(const std::string& key, const StreamProfile& profile) const {
    for (const auto& e : m_rings) {
        const FrameRingLayout& l = e->ring->layout();
        if (e->key == key && static_cast<int>(l.width) == profile.width &&
            static_cast<int>(l.height) == profile.height && l.format == profile.format) {
            return e;
        }
    }
    return nullptr;
}

Status RingSet::checkMemory(const StreamProfile& profile) {
    // The memory ceiling: a new ring must fit next to the ones that exist.
    const FrameRingLayout want = FrameRingLayout::make(m_options.ring_slots, static_cast<std::uint32_t>(profile.width),
                                                       static_cast<std::uint32_t>(profile.height), profile.format);
    const std::size_t used = totalBytes();
    if (m_options.ring_memory_bytes == 0 || used + want.total_bytes <= m_options.ring_memory_bytes) {
        return {};
    }
    m_stats.count(&FrameServerStats::refused_ring_memory);
    const std::size_t idle = idleCount();
    return Error{
        "ring memory: " + profile.view + " " + std::to_string(profile.width) + "x" + std::to_string(profile.height) +
        " " + pixelFormatName(profile.format) + " needs " + sizeText(want.total_bytes) + ", " + sizeText(used) +
        " of " + sizeText(m_options.ring_memory_bytes) + " are in use" +
        (idle == 0 ? std::string()
                   : " (" + std::to_string(idle) + (idle == 1 ? " idle ring" : " idle rings") + " kept for reuse)") +
        "; try again later"};
}

Result<std::shared_ptr<RingEntry>> RingSet::attach(const std::string& key, const StreamProfile& profile) {
    if (auto e = find(key, profile)) {
        if (e->clients == 0) {
            // An idle ring comes back: what it holds was rendered before, for clients now gone.
            // New clients get frames rendered from now on, as from a new ring.
            const std::uint64_t latest = e->ring->latestSequence();
            e->first_seq = latest + 1;
            e->zlib_asked = e->jpeg_asked = latest;
            e->zlib.reset();
            e->jpeg.reset();
            e->max_fps = 0;
            m_stats.count(&FrameServerStats::rings_reused);
        }
        ++e->clients;
        e->max_fps = std::max(e->max_fps, effectiveFps(profile.fps));
        return e;
    }
    if (auto room = checkMemory(profile); !room) {
        return Error{room.message()};
    }
    const std::string name = "navmap-ring-" + key + "-" + std::to_string(profile.width) + "x" +
                             std::to_string(profile.height) + "-" + pixelFormatName(profile.format) + "-" +
                             std::to_string(++m_ring_counter);
    auto ring = FrameRing::create(name, m_options.ring_slots, static_cast<std::uint32_t>(profile.width),
                                  static_cast<std::uint32_t>(profile.height), profile.format);
    if (!ring) {
        return Error{ring.error().message};
    }
    auto e = std::make_shared<RingEntry>();
    e->key = key;
    e->view = profile.view;
    e->ring = std::shared_ptr<FrameRing>(std::move(ring.value()));
    e->clients = 1;
    e->max_fps = effectiveFps(profile.fps);
    m_rings.push_back(e);
    return e;
}

void RingSet::retireUnused() {
    // A ring a client was given stays: the client may have mapped it, and a mapping lives on
    // after its descriptor is closed and its connection is gone, in that process or any it
    // passed the descriptor to or forked, out of the server's sight. Freeing such a ring and
    // making a new one for the next client would leave the old memory in use but no longer
    // counted: a client that connects, maps, closes and disconnects in a loop would grow shared
    // memory by one ring per cycle past ring_memory_bytes. Keeping it bounds the memory rings
    // can ever take to the distinct (profile, size, format) that fit under the ceiling, all of
    // them counted; it is reused by the next client of the same profile, size and format.
    // (Counting a freed ring until its last mapping is gone cannot be done: the server cannot
    // see other processes' mappings. A rate limit on creations would only slow the growth.)
    const auto freed = [](const auto& e) { return e->clients == 0 && !e->handed_out; };
    for (const auto& e : m_rings) {
        if (freed(e)) {
            m_retired_pinned_overwrites += e->ring->pinnedOverwrites();
        }
    }
    std::erase_if(m_rings, freed);
}

std::size_t RingSet::activeCount() const {
    return static_cast<std::size_t>(
        std::count_if(m_rings.begin(), m_rings.end(), [](const auto& e) { return e->clients > 0; }));
}

std::size_t RingSet::idleCount() const { return m_rings.size() - activeCount(); }

std::uint64_t RingSet::pinnedOverwrites() const {
    std::uint64_t total = m_retired_pinned_overwrites;
    for (const auto& e : m_rings) {
        total += e->ring->pinnedOverwrites();
    }
    return total;
}

std::size_t RingSet::totalBytes() const {
    std::size_t total = 0;
    for (const auto& e : m_rings) {
        total += e->ring->layout().total_bytes;
    }
    return total;
}

void RingSet::takeEncodes(std::vector<FrameEncoder::Result> results) {
    for (auto& r : results) {
        for (const auto& e : m_rings) {
            if (e->ring.get() == r.ring) {
                auto& slot = r.kind == EncodeKind::Zlib ? e->zlib : e->jpeg;
                // An encode asked for before the ring was idle is of no use to its new clients.
                if (r.frame->sequence >= e->first_seq && (!slot || r.frame->sequence > slot->sequence)) {
                    slot = std::move(r.frame);
                }
                break;
            }
        }
    }
}

std::vector<ActiveProfile> RingSet::activeProfiles() const {
    std::vector<ActiveProfile> active;
    for (const auto& e : m_rings) {
        if (e->clients == 0) {
            continue;  // idle: nothing to render for it
        }
        const FrameRingLayout& l = e->ring->layout();
        bool merged = false;
        for (auto& a : active) {
            if (a.profile == e->key && a.width == static_cast<int>(l.width) && a.height == static_cast<int>(l.height)) {
                a.clients += e->clients;
                a.dmabuf_clients += e->dmabuf_clients;
                a.max_fps = std::max(a.max_fps, e->max_fps);
                merged = true;
            }
        }
        if (!merged) {
            active.push_back({e->key, e->view, static_cast<int>(l.width), static_cast<int>(l.height), e->max_fps,
                              e->clients, e->dmabuf_clients});
        }
    }
    return active;
}

void RingSet::updatePublishSet() {
    auto set = std::make_shared<PublishSet>();
    for (const auto& e : m_rings) {
        if (e->clients > 0) {
            const FrameRingLayout& l = e->ring->layout();
            set->push_back({e->key, e->ring, e->meta, e->dmabuf_clients > 0 ? e->dmabuf : nullptr, l.width, l.height});
        }
    }
    std::lock_guard lock(m_publish_mutex);
    m_publish_set = std::move(set);
}

std::size_t RingSet::publish(const std::string& profile, const FrameView& frame) {
    std::shared_ptr<const PublishSet> set;
    {
        std::lock_guard lock(m_publish_mutex);
        set = m_publish_set;
    }
    std::size_t written = 0;
    for (const auto& t : *set) {
        if (t.key != profile) {
            continue;
        }
        // The block first: the server thread may send the frame as soon as write() returns.
        t.meta->put(t.ring->nextSequence(), frame.meta);
        if (t.ring->write(frame) != 0) {
            ++written;
        }
    }
    return written;
}

std::size_t RingSet::publishDmabuf(const std::string& profile, const FrameView& info, const DmabufBuffer& buffer) {
    std::shared_ptr<const PublishSet> set;
    {
        std::lock_guard lock(m_publish_mutex);
        set = m_publish_set;
    }
    std::size_t reached = 0;
    int fence = buffer.fence_fd;  // one publish() takes it; the others get their own duplicate
    for (const auto& t : *set) {
        if (t.key != profile || !t.dmabuf || t.width != buffer.layout.width || t.height != buffer.layout.height) {
            continue;
        }
        DmabufBuffer b = buffer;
        b.fence_fd = reached == 0 ? fence : (fence >= 0 ? ::fcntl(fence, F_DUPFD_CLOEXEC, 0) : -1);
        if (t.dmabuf->publish(info, b)) {
            ++reached;
        } else if (reached == 0) {
            fence = -1;  // publish() closed it
        }
    }
    if (reached == 0 && fence >= 0) {
        ::close(fence);
    }
    return reached;
}

std::uint32_t RingSet::dmabufBusy(const std::string& profile) const {
    std::shared_ptr<const PublishSet> set;
    {
        std::lock_guard lock(m_publish_mutex);
        set = m_publish_set;
    }
    std::uint32_t busy = 0;
    for (const auto& t : *set) {
        if (t.key == profile && t.dmabuf) busy |= t.dmabuf->busy();
    }
    return busy;
}

void RingSet::clear() {
    m_rings.clear();
    std::lock_guard lock(m_publish_mutex);
    m_publish_set = std::make_shared<PublishSet>();
}

}  // namespace navmap::ipc::stream_detail
