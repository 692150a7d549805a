// SPDX-License-Identifier: Apache-2.0
#include "frame_encoder.h"

#include <turbojpeg.h>
#include <zlib.h>

#include <algorithm>
#include <chrono>

#include "navmap/common/check.h"

namespace navmap::ipc::stream_detail {

namespace {

using Clock = std::chrono::steady_clock;

double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

}  // namespace

FrameEncoder::FrameEncoder(int jpeg_quality, std::function<void()> wake)
    : m_jpeg_quality(std::clamp(jpeg_quality, 1, 100)), m_wake(std::move(wake)) {}

FrameEncoder::~FrameEncoder() {
    stop();
    if (m_tj != nullptr) tjDestroy(static_cast<tjhandle>(m_tj));
}

Status FrameEncoder::start() {
    if (m_thread.joinable()) return {};
    if (m_tj == nullptr) {
        m_tj = tjInitCompress();
        if (m_tj == nullptr) return Error{std::string("tjInitCompress(MJPEG): ") + tjGetErrorStr2(nullptr)};
    }
    {
        std::lock_guard lock(m_mutex);
        m_running = true;
    }
    m_thread = std::thread([this] { run(); });
    return {};
}

void FrameEncoder::stop() {
    {
        std::lock_guard lock(m_mutex);
        m_running = false;
        m_jobs.clear();
    }
    m_cv.notify_all();
    if (m_thread.joinable()) m_thread.join();
    std::lock_guard lock(m_mutex);
    m_results.clear();
}

void FrameEncoder::request(const std::shared_ptr<FrameRing>& ring, std::uint64_t sequence, EncodeKind kind) {
    {
        std::lock_guard lock(m_mutex);
        Job& job = m_jobs[Key{ring.get(), kind}];
        if (job.ring) ++m_stats.replaced;  // not started yet: the newer frame takes its place
        job.ring = ring;
        job.sequence = sequence;
    }
    m_cv.notify_one();
}

std::vector<FrameEncoder::Result> FrameEncoder::takeResults() {
    std::lock_guard lock(m_mutex);
    return std::exchange(m_results, {});
}

EncoderStats FrameEncoder::stats() const {
    std::lock_guard lock(m_mutex);
    return m_stats;
}

void FrameEncoder::run() {
    std::unique_lock lock(m_mutex);
    while (true) {
        m_cv.wait(lock, [this] { return !m_running || !m_jobs.empty(); });
        if (!m_running) return;
        // Round robin over (ring, kind): the next key after the one served last. A ring's newer
        // request replaces its waiting one, so while one format takes longer than a frame
        // period, the other formats and rings still get their turn.
        auto it = m_served ? m_jobs.upper_bound(*m_served) : m_jobs.begin();
        if (it == m_jobs.end()) it = m_jobs.begin();
        m_served = it->first;
        const Key key = it->first;
        Job job = std::move(it->second);
        m_jobs.erase(it);
        lock.unlock();
        auto frame = encode(*job.ring, job.sequence, key.second);
        job.ring.reset();
        lock.lock();
        if (!frame) continue;
        m_results.push_back({key.first, key.second, std::move(frame)});
        lock.unlock();
        if (m_wake) m_wake();
        lock.lock();
    }
}

std::shared_ptr<const EncodedFrame> FrameEncoder::encode(const FrameRing& ring, std::uint64_t sequence,
                                                         EncodeKind kind) {
    const auto t0 = Clock::now();
    const FrameRingLayout& l = ring.layout();
    auto out = std::make_shared<EncodedFrame>();
    m_pixels.resize(l.pixelBytes());
    // The frame may have been overwritten since the request (a ring of 4 slots, a slow encode):
    // then the newest one is as good.
    bool ok = ring.read(sequence, &out->header, m_pixels.data());
    if (!ok) {
        sequence = ring.latestSequence();
        ok = ring.read(sequence, &out->header, m_pixels.data());
    }
    std::string error;
    if (ok) {
        out->sequence = sequence;
        if (kind == EncodeKind::Zlib) {
            uLongf zlen = compressBound(static_cast<uLong>(m_pixels.size()));
            out->bytes.resize(zlen);
            // Level 1: map frames have large flat areas; speed matters more than the last 10%.
            if (compress2(out->bytes.data(), &zlen, m_pixels.data(), static_cast<uLong>(m_pixels.size()), 1) != Z_OK) {
                ok = false;
                error = "compress2 failed";
            }
            out->bytes.resize(zlen);
        } else {
            const std::uint8_t* src = m_pixels.data();
            int pitch = static_cast<int>(l.stride);
            if (l.format != PixelFormat::Rgba8) {
                m_rgba.resize(static_cast<std::size_t>(l.width) * l.height * 4);
                for (std::uint32_t y = 0; y < l.height; ++y) {
                    convertRowToRgba(m_pixels.data() + static_cast<std::size_t>(l.stride) * y, l.format,
                                     m_rgba.data() + static_cast<std::size_t>(l.width) * 4 * y,
                                     static_cast<int>(l.width));
                }
                src = m_rgba.data();
                pitch = static_cast<int>(l.width * 4);
            }
            auto* tj = static_cast<tjhandle>(m_tj);
            NAVMAP_CHECK(static_cast<std::uint32_t>(pitch) >= l.width * 4,
                         "JPEG source rows shorter than the frame width");
            out->bytes.resize(tjBufSize(static_cast<int>(l.width), static_cast<int>(l.height), TJSAMP_420));
            unsigned char* dst = out->bytes.data();
            unsigned long size = out->bytes.size();
            if (tjCompress2(tj, src, static_cast<int>(l.width), pitch, static_cast<int>(l.height), TJPF_RGBA, &dst,
                            &size, TJSAMP_420, m_jpeg_quality, TJFLAG_NOREALLOC | TJFLAG_FASTDCT) != 0) {
                ok = false;
                error = std::string("tjCompress2(MJPEG): ") + tjGetErrorStr2(tj);
            }
            out->bytes.resize(size);
        }
    }
    const double ms = msSince(t0);
    std::lock_guard lock(m_mutex);
    if (!ok) {
        ++m_stats.failed;
        if (!error.empty()) m_stats.last_error = error;
        return nullptr;
    }
    ++m_stats.encoded;
    double& last = kind == EncodeKind::Zlib ? m_stats.zlib_ms_last : m_stats.jpeg_ms_last;
    double& max = kind == EncodeKind::Zlib ? m_stats.zlib_ms_max : m_stats.jpeg_ms_max;
    last = ms;
    max = std::max(max, ms);
    return out;
}

}  // namespace navmap::ipc::stream_detail
