// SPDX-License-Identifier: Apache-2.0
// vcan_check: runs INSIDE the qemu guest started by sim/vcan/run_vcan_test.sh, against a real
// Linux vcan interface. It replays a real Ford log into vcan0 with can-utils' canplayer and checks
// what SocketCanSource + VehicleDecoder received: kernel-filtered ids, kernel timestamps, decoded
// speed, error frames, CAN FD, kernel drop counts (SO_RXQ_OVFL) and re-open after down/up.
// Prints "VCAN_CHECK <name>: ok|FAIL <details>" lines and exits 0 when all checks pass.
//
// usage: vcan_check <interface> <candump log> <canplayer> <dbc dir> <signal map toml> <navmap.dbc>

#include <spawn.h>
#include <sys/wait.h>

#include <linux/can/error.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <thread>

#include "navmap/ipc/can/candump_reader.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/signal_map.h"
#include "navmap/ipc/can/socketcan_source.h"
#include "navmap/ipc/can/vehicle_decoder.h"

extern char** environ;

namespace ipc = navmap::ipc;
using namespace std::chrono_literals;

namespace {

int g_failures = 0;

void check(const char* name, bool ok, const std::string& details) {
    std::printf("VCAN_CHECK %s: %s %s\n", name, ok ? "ok" : "FAIL", details.c_str());
    std::fflush(stdout);
    if (!ok) {
        ++g_failures;
    }
}

std::shared_ptr<const ipc::DbcDatabase> load(const std::string& path) {
    return std::make_shared<const ipc::DbcDatabase>(ipc::DbcDatabase::loadOrThrow(path));
}

int run(const std::string& cmd) {
    const int rc = std::system(cmd.c_str());
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 7) {
        std::fprintf(stderr, "usage: %s <iface> <log> <canplayer> <dbc dir> <map.toml> <navmap.dbc>\n", argv[0]);
        return 2;
    }
    const std::string iface = argv[1];
    const std::string log_path = argv[2];
    const std::string canplayer = argv[3];
    const std::string dbc_dir = argv[4];

    auto map = ipc::SignalMap::loadToml(argv[5]).value();
    for (const auto& m : ipc::SignalMap::navmapDefaults().mappings()) {
        map.add(m);
    }
    auto decoder = ipc::VehicleDecoder::create({load(dbc_dir + "/ford_lincoln_base_pt.dbc"),
                                                load(dbc_dir + "/ford_fusion_2018_pt.dbc"), load(argv[6])},
                                               map)
                       .value();
    const auto keys = decoder.frameKeys();
    const std::set<std::uint32_t> key_set(keys.begin(), keys.end());

    // Expected: the log's frames whose id is mapped.
    const auto log = ipc::loadCandumpFile(log_path).value();
    std::size_t expected_frames = 0;
    for (const auto& r : log.records) {
        expected_frames += key_set.count(r.frame.key());
    }

    ipc::SocketCanOptions opt;
    opt.interface_name = iface;
    opt.frame_keys = keys;
    opt.backoff_initial = 50ms;
    opt.backoff_maximum = 400ms;
    ipc::SocketCanSource rx(opt);

    double vmin = 1e9;
    double vmax = -1e9;
    std::size_t frames = 0;
    std::size_t unmapped = 0;
    ipc::CanTime first_stamp{};
    ipc::CanTime last_stamp{};
    bool monotonic = true;
    std::size_t fd_frames = 0;
    ipc::VehicleSample u;
    const auto sink = [&](const ipc::CanFrame& f) {
        ++frames;
        if (key_set.count(f.key()) == 0) {
            ++unmapped;
        }
        if (f.fd()) {
            ++fd_frames;
        }
        if (first_stamp == ipc::CanTime{}) {
            first_stamp = f.timestamp;
        }
        monotonic = monotonic && f.timestamp >= last_stamp;
        last_stamp = f.timestamp;
        if (decoder.decode(f, u)) {
            if (const auto v = u.get(ipc::VssSignal::Speed)) {
                vmin = std::min(vmin, *v);
                vmax = std::max(vmax, *v);
            }
        }
    };
    rx.poll(sink);
    check("open", rx.status().state == ipc::SocketCanStatus::State::Open,
          "state=" + std::string(ipc::SocketCanStatus::stateName(rx.status().state)) + " " + rx.status().last_error +
              " fd=" + (rx.status().fd_enabled ? "yes" : "no"));

    // 1. Real log through canplayer with its original timing.
    pid_t pid = 0;
    std::string arg0 = canplayer;
    std::string arg1 = "-I";
    std::string arg2 = log_path;
    char* args[] = {arg0.data(), arg1.data(), arg2.data(), nullptr};
    const auto sent = ipc::CanClock::now();
    if (posix_spawn(&pid, canplayer.c_str(), nullptr, nullptr, args, environ) != 0) {
        check("canplayer", false, "posix_spawn(" + canplayer + ") failed");
        return 1;
    }
    int status = 0;
    bool exited = false;
    auto idle_since = std::chrono::steady_clock::now();
    while (true) {
        rx.waitReadable(20ms);
        if (rx.poll(sink, 1024) > 0) {
            idle_since = std::chrono::steady_clock::now();
        }
        if (!exited && waitpid(pid, &status, WNOHANG) == pid) {
            exited = true;
        }
        if (exited && std::chrono::steady_clock::now() - idle_since > 300ms) {
            break;
        }
    }
    check("canplayer", WIFEXITED(status) && WEXITSTATUS(status) == 0, "exit status " + std::to_string(status));
    check("filter", frames == expected_frames && unmapped == 0,
          "received " + std::to_string(frames) + " of " + std::to_string(expected_frames) + " mapped frames (log has " +
              std::to_string(log.records.size()) + "), unmapped " + std::to_string(unmapped));
    const double span_s = std::chrono::duration<double>(last_stamp - first_stamp).count();
    const double skew_s = std::chrono::duration<double>(first_stamp - sent).count();
    check("timestamps", monotonic && span_s > 1.0 && span_s < 3.0 && skew_s > -1.0 && skew_s < 5.0,
          "kernel timestamps span " + std::to_string(span_s) + " s, first " + std::to_string(skew_s) +
              " s after spawning canplayer");
    check(
        "speed", vmin > 102.6 && vmax < 103.8 && vmax > 102.6,
        "decoded Vehicle.Speed " + std::to_string(vmin) + ".." + std::to_string(vmax) + " km/h (expected 102.7-103.7)");
    check("kernel_drops_none", rx.status().kernel_drops == 0, std::to_string(rx.status().kernel_drops));

    // 2. Error frame (bus-off) and a CAN FD frame through a second socket.
    ipc::SocketCanOptions tx_opt;
    tx_opt.interface_name = iface;
    ipc::SocketCanSource tx(tx_opt);
    tx.poll([](const ipc::CanFrame&) {});
    ipc::CanFrame err;
    err.flags = ipc::kCanError;
    err.id = CAN_ERR_BUSOFF | CAN_ERR_CRTL;
    err.len = 8;
    err.data[1] = CAN_ERR_CRTL_RX_PASSIVE;
    const auto err_sent = tx.send(err);
    ipc::CanFrame fd;
    fd.id = 0x6A0;
    fd.flags = ipc::kCanFd | ipc::kCanBrs;
    fd.len = 64;
    const auto nav = load(argv[6]);
    const auto pos = nav->findMessage(std::string_view("NAV_Position"))
                         ->encode({{"NAV_Latitude", 42.623636}, {"NAV_Longitude", 1.532909}})
                         .value();
    std::copy(pos.data.begin(), pos.data.begin() + 8, fd.data.begin());
    const auto fd_sent = tx.send(fd);
    for (int i = 0; i < 20; ++i) {
        rx.waitReadable(20ms);
        rx.poll(sink);
    }
    check("error_frame", err_sent.ok() && rx.status().bus_off == 1 && rx.status().controller_problems == 1,
          (err_sent.ok() ? std::string() : err_sent.message() + " ") + "busOff=" + std::to_string(rx.status().bus_off) +
              " last='" + rx.status().last_error_frame + "'");
    const auto lat = decoder.latest().get(ipc::VssSignal::Latitude);
    check("can_fd", fd_sent.ok() && fd_frames == 1 && lat && std::abs(*lat - 42.623636) < 1e-6,
          (fd_sent.ok() ? std::string() : fd_sent.message() + " ") + "fd frames " + std::to_string(fd_frames));

    // 3. Kernel drop counting: a receiver with a tiny buffer that does not read while 2000 frames
    //    are sent.
    ipc::SocketCanOptions small_opt;
    small_opt.interface_name = iface;
    small_opt.receive_buffer_bytes = 1;  // the kernel rounds up to its minimum
    ipc::SocketCanSource small(small_opt);
    small.poll([](const ipc::CanFrame&) {});
    ipc::CanFrame burst;
    burst.id = 0x415;
    burst.len = 8;
    int sent_ok = 0;
    for (int i = 0; i < 2000; ++i) {
        burst.data[0] = static_cast<std::uint8_t>(i);
        sent_ok += tx.send(burst).ok() ? 1 : 0;
    }
    std::size_t small_frames = 0;
    small.poll([&](const ipc::CanFrame&) { ++small_frames; }, 5000);
    // The kernel attaches the drop count (SO_RXQ_OVFL) to frames queued after the drops, so one
    // more frame brings the news.
    sent_ok += tx.send(burst).ok() ? 1 : 0;
    small.waitReadable(100ms);
    small.poll([&](const ipc::CanFrame&) { ++small_frames; }, 5000);
    check("kernel_drops",
          small.status().kernel_drops > 0 &&
              small_frames + small.status().kernel_drops == static_cast<std::size_t>(sent_ok),
          "sent " + std::to_string(sent_ok) + ", read " + std::to_string(small_frames) + ", SO_RXQ_OVFL drops " +
              std::to_string(small.status().kernel_drops));
    rx.poll([](const ipc::CanFrame&) {}, 100000);  // drain

    // 4. Interface down and up again: the source re-opens with backoff.
    run("ip link set " + iface + " down");
    for (int i = 0; i < 5; ++i) {
        rx.poll(sink);
        std::this_thread::sleep_for(10ms);
    }
    const auto down_state = rx.status().state;
    const std::string down_error = rx.status().last_error;
    run("ip link set " + iface + " up");
    for (int i = 0; i < 100 && rx.status().state != ipc::SocketCanStatus::State::Open; ++i) {
        rx.waitReadable(20ms);
        rx.poll(sink);
    }
    ipc::SocketCanSource tx2(tx_opt);
    tx2.poll([](const ipc::CanFrame&) {});
    const std::size_t before = frames;
    ipc::CanFrame after = pos;
    after.timestamp = {};
    (void)tx2.send(after);
    for (int i = 0; i < 10 && frames == before; ++i) {
        rx.waitReadable(20ms);
        rx.poll(sink);
    }
    check("reopen",
          down_state == ipc::SocketCanStatus::State::Retrying && rx.status().opens >= 2 && frames == before + 1,
          "after down: " + std::string(ipc::SocketCanStatus::stateName(down_state)) + " '" + down_error + "'; opens=" +
              std::to_string(rx.status().opens) + " openFailures=" + std::to_string(rx.status().open_failures) +
              " frame after up: " + (frames == before + 1 ? "yes" : "no"));

    std::printf("VCAN_SUMMARY failures=%d\n", g_failures);
    return g_failures == 0 ? 0 : 1;
}
