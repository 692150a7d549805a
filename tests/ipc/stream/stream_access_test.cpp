// FrameServer against hostile local clients: rings no client can write.

#include <gtest/gtest.h>
#include <fcntl.h>
#include <linux/falloc.h>
#include <sys/mman.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cstring>
#include <nlohmann/json.hpp>

#include "navmap/ipc/frame_header.h"
#include "navmap/ipc/frame_ring.h"
#include "navmap/ipc/frame_server.h"
#include "navmap/ipc/stream_client.h"
#include "stream_test_util.h"

using namespace navmap::ipc;
using namespace navmap::stream_test;
using namespace std::chrono_literals;

namespace {

StreamRequest request(const std::string& view, int width, int height, StreamPayload payload = StreamPayload::Shm,
                      PixelFormat format = PixelFormat::Rgba8) {
    StreamRequest r;
    r.profile.name = "test";
    r.profile.view = view;
    r.profile.width = width;
    r.profile.height = height;
    r.profile.fps = 0;
    r.profile.format = format;
    r.payload = payload;
    return r;
}

// A server for one test, and the fd count around it.
class StreamAccessTest : public ::testing::Test {
protected:
    void SetUp() override { m_fdsBefore = countOpenFds(); }
    void TearDown() override {
        m_server.reset();
        EXPECT_EQ(countOpenFds(), m_fdsBefore) << "descriptors leaked";
    }
    FrameServerOptions options() const {
        FrameServerOptions o;
        o.unixPath = uniqueSocketPath("stream-access");
        o.stallTimeout = 2s;
        return o;
    }
    void start(FrameServerOptions o) {
        m_server = std::make_unique<FrameServer>(std::move(o));
        const auto st = m_server->start();
        ASSERT_TRUE(st.ok()) << st.message();
    }
    const std::string& path() const { return m_server->options().unixPath; }
    template <typename Pred>
    bool waitFor(Pred pred, std::chrono::milliseconds limit = 5s) {
        const auto until = std::chrono::steady_clock::now() + limit;
        while (std::chrono::steady_clock::now() < until) {
            if (pred()) {
                return true;
            }
            std::this_thread::sleep_for(5ms);
        }
        return pred();
    }
    // One frame for `client` within `limit`; the pixels must be the Publisher's pattern.
    static void expectFrame(StreamClient& client, std::chrono::milliseconds limit = 3s) {
        ReceivedFrame f;
        const auto until = std::chrono::steady_clock::now() + limit;
        while (std::chrono::steady_clock::now() < until) {
            auto r = client.next(f, 100ms);
            ASSERT_TRUE(r.ok()) << r.error().message;
            if (r.value()) {
                ASSERT_EQ(f.pixels.size(), f.header.pixelBytes());
                const auto want = sequencePattern(static_cast<int>(f.header.width), static_cast<int>(f.header.height),
                                                  f.header.sequence);
                EXPECT_EQ(0, std::memcmp(f.pixels.data(), want.data(), want.size()));
                return;
            }
        }
        FAIL() << "no frame within " << limit.count() << " ms";
    }

    int m_fdsBefore = 0;
    std::unique_ptr<FrameServer> m_server;
};

}  // namespace

TEST_F(StreamAccessTest, NoClientCanMakeTheRingWritable) {
    start(options());
    auto raw = rawShmHandshake(path(), formatStreamRequest(request("bird", 64, 32)));
    ASSERT_NE(raw->reply.find("\"ok\":true"), std::string::npos) << raw->reply;
    ASSERT_GE(raw->ringFd, 0) << "no descriptor with the reply";
    const int fd = raw->ringFd;
    const std::size_t bytes = FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8).totalBytes;
    const int seals = ::fcntl(fd, F_GET_SEALS);
    EXPECT_EQ(seals, F_SEAL_SEAL | F_SEAL_SHRINK | F_SEAL_GROW | F_SEAL_FUTURE_WRITE) << std::hex << seals;

    // The descriptor as received: read-only.
    errno = 0;
    EXPECT_EQ(::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, fd, 0), MAP_FAILED);
    EXPECT_EQ(errno, EACCES);
    void* ro = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, fd, 0);
    ASSERT_NE(ro, MAP_FAILED);
    EXPECT_EQ(::mprotect(ro, bytes, PROT_READ | PROT_WRITE), -1);

    // Re-opened read-write through /proc: it opens, but nothing can write through it.
    const std::string proc = "/proc/self/fd/" + std::to_string(fd);
    const int rw = ::open(proc.c_str(), O_RDWR | O_CLOEXEC);
    ASSERT_GE(rw, 0) << std::strerror(errno);
    errno = 0;
    EXPECT_EQ(::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_SHARED, rw, 0), MAP_FAILED);
    EXPECT_EQ(errno, EPERM);
    void* rwRead = ::mmap(nullptr, bytes, PROT_READ, MAP_SHARED, rw, 0);
    ASSERT_NE(rwRead, MAP_FAILED);
    EXPECT_EQ(::mprotect(rwRead, bytes, PROT_READ | PROT_WRITE), -1);
    const char junk[16] = "drawn by client";
    EXPECT_EQ(::pwrite(rw, junk, sizeof(junk), 4096 + 256), -1);
    EXPECT_EQ(errno, EPERM);
    EXPECT_EQ(::fallocate(rw, FALLOC_FL_PUNCH_HOLE | FALLOC_FL_KEEP_SIZE, 4096, 4096), -1);
    EXPECT_EQ(errno, EPERM);
    EXPECT_EQ(::ftruncate(rw, 0), -1);
    // A private writable mapping is possible, but its writes are copies nobody else sees.
    void* priv = ::mmap(nullptr, bytes, PROT_READ | PROT_WRITE, MAP_PRIVATE, rw, 0);
    ASSERT_NE(priv, MAP_FAILED);
    std::memset(static_cast<std::uint8_t*>(priv) + 4096, 0x5A, bytes - 4096);

    // Frames still arrive whole, to this client and to another one.
    auto other = StreamClient::connectUnix(path(), request("bird", 64, 32));
    ASSERT_TRUE(other.ok()) << other.error().message;
    const auto px = sequencePattern(64, 32, 1);
    ASSERT_EQ(m_server->publish("bird", FrameView{px.data(), 64, 32, 0, PixelFormat::Rgba8, 0, 0}), 1U);
    ReceivedFrame f;
    auto r = other.value()->next(f, 3s);
    ASSERT_TRUE(r.ok() && r.value()) << (r.ok() ? "timeout" : r.error().message);
    EXPECT_EQ(0, std::memcmp(f.pixels.data(), px.data(), px.size()));
    const auto layout = FrameRingLayout::make(3, 64, 32, PixelFormat::Rgba8);
    std::vector<std::uint8_t> mine(layout.pixelBytes());
    FrameHeader h;
    ASSERT_TRUE(FrameRing::readMapped(static_cast<const std::uint8_t*>(ro), layout, 1, &h, mine.data()));
    EXPECT_EQ(mine, px);
    ::munmap(priv, bytes);
    ::munmap(rwRead, bytes);
    ::munmap(ro, bytes);
    ::close(rw);
}
