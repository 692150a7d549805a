// SPDX-License-Identifier: Apache-2.0
// Frame-stream benchmarks (Google Benchmark, JSON with --benchmark_format=json):
//  - BM_Deliver/<transport>/<w>/<h>: publish -> client has the pixels, in lock step; frames/s is
//    items_per_second (the transport's ceiling on this machine, one client);
//  - BM_Publish/<clients>/<format>/<w>/<h>: what publish() costs the render thread with a shm
//    client attached (target: < 1 ms per frame at 1280x720);
//  - BM_ConvertFrame/<format>/<w>/<h>: the RGBA8 -> ring format conversion alone, per frame.
// Frames look like a map (flat land-cover areas, roads, some texture), so zlib and JPEG sizes are
// realistic rather than best or worst case.

#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>
#include <random>
#include <vector>

#include "navmap/ipc/client/frame_format.h"
#include "navmap/ipc/client/stream_client.h"
#include "navmap/ipc/client/zlib_inflater.h"
#include "navmap/ipc/stream/frame_server.h"
#include "stream_test_util.h"

using namespace navmap::ipc;
using namespace std::chrono_literals;

namespace {

std::vector<std::uint8_t> mapLikeFrame(int w, int h, int variant) {
    std::vector<std::uint8_t> px(static_cast<std::size_t>(w) * h * 4);
    std::mt19937 rng(static_cast<unsigned>(variant));
    for (int y = 0; y < h; ++y) {
        for (int x = 0; x < w; ++x) {
            std::uint8_t* p = &px[(static_cast<std::size_t>(y) * w + x) * 4];
            const bool forest = std::sin((x + variant) * 0.013) + std::cos(y * 0.021) > 0.4;
            const bool road = std::abs((x + variant * 3) % 211 - 100) < 4 || std::abs((y + x / 3) % 157 - 70) < 3;
            const int noise = static_cast<int>(rng() % 9) - 4;
            p[0] = static_cast<std::uint8_t>((road ? 250 : forest ? 90 : 200) + (road ? 0 : noise));
            p[1] = static_cast<std::uint8_t>((road ? 220 : forest ? 140 : 205) + (road ? 0 : noise));
            p[2] = static_cast<std::uint8_t>((road ? 120 : forest ? 80 : 180) + (road ? 0 : noise));
            p[3] = 255;
        }
    }
    return px;
}

FrameServerOptions serverOptions() {
    FrameServerOptions o;
    o.unix_path = navmap::stream_test::uniqueSocketPath("stream-bench");
    o.tcp_port = 0;
    o.http_port = 0;
    return o;
}

StreamRequest request(int w, int h, StreamPayload payload, PixelFormat format = PixelFormat::Rgba8) {
    StreamRequest r;
    r.profile.name = "bench";
    r.profile.width = w;
    r.profile.height = h;
    r.profile.view = "bird";
    r.profile.fps = 0;  // every frame: measure the transport, not the rate cap
    r.profile.format = format;
    r.payload = payload;
    return r;
}

// transport: 0 shm, 1 tcp raw, 2 tcp zlib, 3 mjpeg (http)
void BM_Deliver(benchmark::State& state) {
    const int transport = static_cast<int>(state.range(0));
    const int w = static_cast<int>(state.range(1));
    const int h = static_cast<int>(state.range(2));
    FrameServer server(serverOptions());
    if (auto s = server.start(); !s) {
        state.SkipWithError(s.message().c_str());
        return;
    }
    const std::vector<std::vector<std::uint8_t>> frames = {mapLikeFrame(w, h, 0), mapLikeFrame(w, h, 17)};
    std::unique_ptr<StreamClient> client;
    std::unique_ptr<navmap::stream_test::MjpegReader> mjpeg;
    if (transport == 3) {
        mjpeg = std::make_unique<navmap::stream_test::MjpegReader>(
            server.httpPort(), "/stream.mjpg?profile=bench&width=" + std::to_string(w) +
                                   "&height=" + std::to_string(h) + "&view=bird&fps=0");
    } else {
        const StreamPayload p = transport == 0   ? StreamPayload::Shm
                                : transport == 1 ? StreamPayload::Raw
                                                 : StreamPayload::Zlib;
        auto c = p == StreamPayload::Shm ? StreamClient::connectUnix(server.options().unix_path, request(w, h, p))
                                         : StreamClient::connectTcp("127.0.0.1", server.tcpPort(), request(w, h, p),
                                                                    std::chrono::seconds(5), zlibInflater());
        if (!c) {
            state.SkipWithError(c.error().message.c_str());
            return;
        }
        client = std::move(c.value());
    }
    while (server.stats().clients == 0) {
        std::this_thread::sleep_for(1ms);
    }
    ReceivedFrame f;
    std::size_t bytes = 0;
    std::int64_t i = 0;
    for (auto _ : state) {
        const auto& px = frames[static_cast<std::size_t>(i++ % 2)];
        server.publish("bird", FrameView{px.data(), w, h, 0, PixelFormat::Rgba8, 0, 0, {}, {}});
        if (mjpeg) {
            const auto jpeg = mjpeg->next(5s);
            if (jpeg.empty()) {
                state.SkipWithError("no MJPEG part");
                return;
            }
            bytes += jpeg.size();
        } else {
            auto r = client->next(f, 5s);
            if (!r.ok() || !r.value()) {
                state.SkipWithError(r.ok() ? "timeout" : r.error().message.c_str());
                return;
            }
        }
    }
    state.SetItemsProcessed(state.iterations());
    if (client) {
        bytes = client->stats().bytes;
    }
    state.counters["wire_bytes_per_frame"] = benchmark::Counter(
        static_cast<double>(bytes) / static_cast<double>(std::max<std::int64_t>(1, state.iterations())));
    static const char* const kNames[] = {"shm", "tcp_raw", "tcp_zlib", "mjpeg_http"};
    state.SetLabel(kNames[transport]);
}

// clients: 0 or 1 shm client draining; format 1 = RGBA8, 2 = RGB565 (converted on publish).
void BM_Publish(benchmark::State& state) {
    const int clients = static_cast<int>(state.range(0));
    const auto format = static_cast<PixelFormat>(state.range(1));
    const int w = static_cast<int>(state.range(2));
    const int h = static_cast<int>(state.range(3));
    FrameServer server(serverOptions());
    if (auto s = server.start(); !s) {
        state.SkipWithError(s.message().c_str());
        return;
    }
    std::atomic<bool> run{true};
    std::thread reader;
    if (clients > 0) {
        auto c = StreamClient::connectUnix(server.options().unix_path, request(w, h, StreamPayload::Shm, format));
        if (!c) {
            state.SkipWithError(c.error().message.c_str());
            return;
        }
        reader = std::thread([&run, cl = std::shared_ptr<StreamClient>(std::move(c.value()))] {
            ReceivedFrame f;
            while (run) {
                if (!cl->next(f, 50ms).ok()) {
                    return;
                }
            }
        });
        while (server.stats().clients == 0) {
            std::this_thread::sleep_for(1ms);
        }
    }
    const auto px = mapLikeFrame(w, h, 3);
    for (auto _ : state) {
        server.publish("bird", FrameView{px.data(), w, h, 0, PixelFormat::Rgba8, 0, 0, {}, {}});
        // A render loop does not publish back to back; give the server thread its turn as a
        // 60 fps loop would (not timed).
        state.PauseTiming();
        std::this_thread::sleep_for(2ms);
        state.ResumeTiming();
    }
    state.SetItemsProcessed(state.iterations());
    run = false;
    if (reader.joinable()) {
        reader.join();
    }
}

void deliverArgs(benchmark::internal::Benchmark* b) {
    for (int t = 0; t < 4; ++t) {
        b->Args({t, 1280, 480})->Args({t, 800, 240})->Args({t, 1280, 720});
    }
}

void publishArgs(benchmark::internal::Benchmark* b) {
    for (const int clients : {0, 1}) {
        b->Args({clients, 1, 1280, 480})->Args({clients, 1, 800, 240})->Args({clients, 1, 1280, 720});
    }
    b->Args({1, 2, 1280, 480})->Args({1, 2, 800, 240})->Args({1, 2, 1280, 720});
}

// The pixel conversion alone (what publish() adds per ring for RGB565): one whole frame per
// iteration; items are pixels, so items_per_second gives the cost per pixel.
void BM_ConvertFrame(benchmark::State& state) {
    const auto format = static_cast<PixelFormat>(state.range(0));
    const int w = static_cast<int>(state.range(1));
    const int h = static_cast<int>(state.range(2));
    const auto px = mapLikeFrame(w, h, 5);
    std::vector<std::uint8_t> out(static_cast<std::size_t>(w) * h * static_cast<std::size_t>(bytesPerPixel(format)));
    const std::size_t out_stride = static_cast<std::size_t>(w) * static_cast<std::size_t>(bytesPerPixel(format));
    for (auto _ : state) {
        for (int y = 0; y < h; ++y) {
            convertRowFromRgba(px.data() + static_cast<std::size_t>(y) * w * 4, format, out.data() + out_stride * y, w);
        }
        benchmark::DoNotOptimize(out.data());
        benchmark::ClobberMemory();
    }
    state.SetItemsProcessed(state.iterations() * w * h);
    state.SetLabel(pixelFormatName(format));
}

void convertArgs(benchmark::internal::Benchmark* b) {
    for (const int format : {1, 2}) {
        b->Args({format, 1280, 480})->Args({format, 800, 240})->Args({format, 1280, 720});
    }
}

}  // namespace

BENCHMARK(BM_Deliver)->Apply(deliverArgs)->Unit(benchmark::kMillisecond)->MinTime(1.0)->UseRealTime();
BENCHMARK(BM_Publish)->Apply(publishArgs)->Unit(benchmark::kMicrosecond)->Iterations(300);
BENCHMARK(BM_ConvertFrame)->Apply(convertArgs)->Unit(benchmark::kMicrosecond)->MinTime(0.3);

BENCHMARK_MAIN();
