// SPDX-License-Identifier: Apache-2.0
// navmap-sim: drives a route through the compiled map and emits the GNSS node's navmap.dbc
// frames to a candump log, to SocketCAN (paced in real time x --speed-factor), and/or hands the
// route to the daemon over the control socket. See docs/simulator.md.
// Exit status: 0 ok, 1 bad input or a failure at run time, 2 usage (docs/tools.md).

#include <poll.h>
#include <signal.h>
#include <sys/signalfd.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <optional>
#include <string>

#include "navmap/cli/cli.h"
#include "navmap/install_layout.h"
#include "navmap/ipc/can/socketcan_source.h"
#include "navmap/ipc/control/control_client.h"
#include "navmap/ipc/net/unique_fd.h"
#include "navmap/sim/candump_writer.h"
#include "navmap/sim/drive_simulator.h"
#include "navmap/sim/route_message.h"
#include "navmap/sim/sim_error.h"

namespace {

using navmap::sim::FrameKind;

// SIGINT/SIGTERM arrive on a signalfd that the pacing loop polls: no handler, no global flag.
class StopSignals {
public:
    StopSignals() {
        sigemptyset(&m_set);
        sigaddset(&m_set, SIGINT);
        sigaddset(&m_set, SIGTERM);
        if (sigprocmask(SIG_BLOCK, &m_set, &m_old) == 0) m_fd.reset(signalfd(-1, &m_set, SFD_CLOEXEC | SFD_NONBLOCK));
    }
    ~StopSignals() {
        m_fd.reset();  // before the old mask comes back
        sigprocmask(SIG_SETMASK, &m_old, nullptr);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;
    /// Sleeps up to `ms` (0: just checks); true when a stop signal arrived.
    bool waitStop(int ms) {
        if (!m_fd.valid()) {
            if (ms > 0) ::usleep(static_cast<useconds_t>(ms) * 1000U);
            return false;
        }
        pollfd p{m_fd.get(), POLLIN, 0};
        if (::poll(&p, 1, ms) > 0) {
            signalfd_siginfo info{};
            return ::read(m_fd.get(), &info, sizeof info) == static_cast<ssize_t>(sizeof info);
        }
        return false;
    }

private:
    sigset_t m_set{};
    sigset_t m_old{};
    navmap::ipc::net::UniqueFd m_fd;
};

struct SimOptions {
    std::string store = navmap::install::defaultStore().string();
    std::string dbc = navmap::install::defaultDbc().string();
    std::string from, to;
    std::string out;
    std::string iface = "can0";
    bool socketcan = false;
    double speed_factor = 1.0;
    std::string route_out;
    std::string control;
    std::string route_id = "r1";
    bool quiet = false;
    double start_time = 1618394400.0;
    navmap::sim::DriveRequest req;  ///< the frame and drive options; store, places and start time from the above
};

void addSimOptions(CLI::App& app, SimOptions& cli) {
    using navmap::cli::finiteIn;
    using navmap::cli::integerIn;
    navmap::sim::DriveRequest& req = cli.req;
    app.add_option("--store", cli.store, "compiled tile store")->capture_default_str();
    app.add_option("--dbc", cli.dbc, "navmap.dbc")->capture_default_str();
    app.add_option("--from", cli.from, "start: \"lat,lon\" or a place name")->required();
    app.add_option("--to", cli.to, "destination: \"lat,lon\" or a place name")->required();
    app.add_option("-o,--out", cli.out, "write a candump log (candump -l format) here");
    app.add_option("--iface", cli.iface, "interface name in the log, and the SocketCAN interface")
        ->capture_default_str();
    app.add_flag("--socketcan", cli.socketcan, "send the frames to --iface over SocketCAN, paced in real time");
    app.add_option("--speed-factor", cli.speed_factor, "SocketCAN pacing: 2 = twice real time, 0 = as fast as possible")
        ->capture_default_str()
        ->check(finiteIn(0.0, 1000.0));
    app.add_option("--duration", req.frames.max_duration_s,
                   "stop after this many seconds of drive time (0 = whole drive)")
        ->check(finiteIn(0.0, 1e7));
    app.add_option("--position-hz", req.frames.position_hz, "NAV_Position rate")
        ->capture_default_str()
        ->check(finiteIn(1.0, 50.0));
    app.add_option("--motion-hz", req.frames.motion_hz, "NAV_Motion rate")
        ->capture_default_str()
        ->check(finiteIn(1.0, 1000.0));
    app.add_option("--info-hz", req.frames.info_hz, "NAV_Info rate (0 = none)")
        ->capture_default_str()
        ->check(finiteIn(0.0, 50.0));
    app.add_option("--noise-m", req.frames.noise_m, "GNSS position noise, sigma per axis in metres")
        ->capture_default_str()
        ->check(finiteIn(0.0, 1000.0));
    app.add_option("--dropouts", req.frames.dropouts, "number of GNSS dropouts (no position frames)")
        ->capture_default_str()
        ->check(integerIn(0, 10000));
    app.add_option("--dropout-s", req.frames.dropout_s, "length of each dropout, seconds")
        ->capture_default_str()
        ->check(finiteIn(0.01, 3600.0));
    app.add_option("--bad-frames", req.frames.bad_bursts, "number of bad-frame bursts")
        ->capture_default_str()
        ->check(integerIn(0, 10000));
    app.add_option("--burst-size", req.frames.burst_frames, "bad frames per burst")
        ->capture_default_str()
        ->check(integerIn(1, 1000));
    app.add_option("--seed", req.frames.seed, "random seed (noise, faults)")
        ->capture_default_str()
        ->check(integerIn(0, std::numeric_limits<long long>::max()));
    app.add_option("--standstill", req.frames.standstill_s, "seconds standing at start and end")
        ->capture_default_str()
        ->check(finiteIn(0.0, 3600.0));
    app.add_option("--start-time", cli.start_time, "log time of the first frame, Unix seconds")
        ->capture_default_str()
        ->check(finiteIn(0.0, 4102444800.0));
    app.add_option("--lateral-accel", req.drive.lateral_accel_mps2, "curve speed limit, m/s^2")
        ->capture_default_str()
        ->check(finiteIn(0.1, 20.0));
    app.add_option("--accel", req.drive.accel_mps2, "acceleration limit, m/s^2")
        ->capture_default_str()
        ->check(finiteIn(0.1, 20.0));
    app.add_option("--brake", req.drive.brake_mps2, "braking limit, m/s^2")
        ->capture_default_str()
        ->check(finiteIn(0.1, 20.0));
    app.add_option("--driver-factor", req.drive.speed_factor, "fraction of the speed limit driven")
        ->capture_default_str()
        ->check(finiteIn(0.1, 2.0));
    app.add_option("--route-out", cli.route_out, "write the set_route JSON line here");
    app.add_option("--control", cli.control, "send set_route to the daemon's control socket");
    app.add_option("--route-id", cli.route_id, "route id in set_route")->capture_default_str();
    app.add_flag("-q,--quiet", cli.quiet, "no progress output");
}

// The route over the control IPC / to a file.
bool publishRoute(const SimOptions& cli, const std::string& msg) {
    if (!cli.route_out.empty()) {
        std::ofstream f(cli.route_out, std::ios::trunc);
        f << msg << '\n';
        if (!f.flush()) {
            std::fprintf(stderr, "navmap-sim: write(%s): failed\n", cli.route_out.c_str());
            return false;
        }
    }
    if (!cli.control.empty()) {
        auto client = navmap::ipc::ControlClient::connect(cli.control);
        if (!client) {
            std::fprintf(stderr, "navmap-sim: set_route: %s\n", client.error().message.c_str());
            return false;
        }
        auto reply = client.value().request(msg);
        if (!reply) {
            std::fprintf(stderr, "navmap-sim: set_route: %s\n", reply.error().message.c_str());
            return false;
        }
        if (!navmap::sim::replyIsOk(reply.value())) {
            std::fprintf(stderr, "navmap-sim: set_route refused: %s\n", reply.value().c_str());
            return false;
        }
        if (!cli.quiet) std::fprintf(stderr, "navmap-sim: set_route accepted: %s\n", reply.value().c_str());
    }
    return true;
}

// Where the frames go: the candump log (-o) and SocketCAN (--socketcan), each when asked for.
bool openOutputs(const SimOptions& cli, std::optional<navmap::sim::CandumpWriter>& log,
                 std::optional<navmap::ipc::SocketCanSource>& can) {
    if (!cli.out.empty()) {
        auto w = navmap::sim::CandumpWriter::open(cli.out, cli.iface);
        if (!w) {
            std::fprintf(stderr, "navmap-sim: %s\n", w.error().message.c_str());
            return false;
        }
        log.emplace(std::move(w).value());
    }
    if (cli.socketcan) {
        navmap::ipc::SocketCanOptions o;
        o.interface_name = cli.iface;
        o.frame_keys = {0x7FF};  // we only send; keep the receive queue quiet
        o.receive_error_frames = false;
        can.emplace(o);
        can->poll([](const navmap::ipc::CanFrame&) {});
        if (can->fd() < 0) {
            std::fprintf(stderr, "navmap-sim: %s\n", can->status().last_error.c_str());
            return false;
        }
    }
    return true;
}

// What sending the frames did.
struct SendOutcome {
    bool write_failed = false;  ///< the log could not be written (reported)
    bool interrupted = false;   ///< SIGINT or SIGTERM
    std::uint64_t send_errors = 0;
    std::string last_send_error;
};

// Sends every frame of the drive to the outputs, paced in real time x --speed-factor on SocketCAN.
SendOutcome sendFrames(const SimOptions& cli, navmap::ipc::CanTime start_time, navmap::sim::FrameGenerator& gen,
                       std::optional<navmap::sim::CandumpWriter>& log, std::optional<navmap::ipc::SocketCanSource>& can,
                       StopSignals& stop) {
    SendOutcome outcome;
    const auto wall0 = std::chrono::steady_clock::now();
    navmap::ipc::CanFrame frame;
    double next_progress = 0.0;
    while (gen.next(frame)) {
        const double t = std::chrono::duration<double>(frame.timestamp - start_time).count();
        if (can && cli.speed_factor > 0.0) {
            const auto due = wall0 + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                         std::chrono::duration<double>(t / cli.speed_factor));
            for (;;) {
                const auto left =
                    std::chrono::duration_cast<std::chrono::milliseconds>(due - std::chrono::steady_clock::now());
                if (stop.waitStop(static_cast<int>(std::max<std::int64_t>(0, left.count())))) {
                    outcome.interrupted = true;
                    break;
                }
                if (left.count() <= 0) break;
            }
        } else if (stop.waitStop(0)) {
            outcome.interrupted = true;
        }
        if (outcome.interrupted) break;
        if (log) {
            if (auto st = log->write(frame); !st) {
                std::fprintf(stderr, "navmap-sim: %s\n", st.message().c_str());
                outcome.write_failed = true;
                return outcome;
            }
        }
        if (can) {
            can->poll([](const navmap::ipc::CanFrame&) {});  // drain other senders' frames
            if (auto st = can->send(frame); !st) {
                ++outcome.send_errors;
                outcome.last_send_error = st.message();
            }
        }
        if (!cli.quiet && t >= next_progress) {
            const auto st = gen.truthAt(t);
            std::fprintf(stderr, "navmap-sim: t=%6.1f s  %6.0f m  %5.1f km/h\n", t, st.measure_m, st.speed_mps * 3.6);
            next_progress += (can && cli.speed_factor > 0.0) ? 5.0 : 60.0;
        }
    }
    return outcome;
}

void printSummary(const SimOptions& cli, const navmap::sim::DriveRequest& req, const navmap::sim::DriveSimulator& sim,
                  const navmap::sim::FrameGenerator& gen, const std::optional<navmap::sim::CandumpWriter>& log,
                  bool can, const SendOutcome& outcome) {
    const auto& route = sim.route();
    const auto& s = gen.stats();
    std::printf("route: %.0f m, %zu points, %zu maneuvers, graph estimate %.0f s\n", route.length(), route.line.size(),
                route.maneuvers.size(), route.graph_duration_s);
    std::printf("drive: %.1f s (%.1f s moving), mean %.1f km/h\n", s.duration_s, sim.profile().duration(),
                sim.profile().duration() > 0 ? route.length() / sim.profile().duration() * 3.6 : 0.0);
    std::printf("frames: %llu", static_cast<unsigned long long>(s.frames));
    for (std::size_t k = 0; k < navmap::sim::kFrameKindCount; ++k) {
        std::printf("%s %s %llu", k == 0 ? " (" : ",", navmap::sim::frameKindName(static_cast<FrameKind>(k)),
                    static_cast<unsigned long long>(s.by_kind[k]));
    }
    std::printf(")\n");
    std::printf("faults: %zu dropouts of %.1f s, %zu bursts of %d bad frames, noise %.1f m, seed %llu\n",
                gen.dropouts().size(), req.frames.dropout_s, gen.burstTimes().size(), req.frames.burst_frames,
                req.frames.noise_m, static_cast<unsigned long long>(req.frames.seed));
    if (log) std::printf("log: %s (%zu lines)\n", cli.out.c_str(), log->lines());
    if (can) {
        std::printf("socketcan: %s, %llu send errors%s%s\n", cli.iface.c_str(),
                    static_cast<unsigned long long>(outcome.send_errors), outcome.send_errors ? ", last: " : "",
                    outcome.last_send_error.c_str());
    }
    if (outcome.interrupted) std::printf("interrupted at %.1f s\n", s.duration_s);
}

int runSim(const SimOptions& cli) {
    navmap::sim::DriveRequest req = cli.req;
    req.store = cli.store;
    req.dbc = cli.dbc;
    req.from = cli.from;
    req.to = cli.to;
    req.frames.start_time = navmap::ipc::CanTime(
        std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::duration<double>(cli.start_time)));

    std::optional<navmap::sim::DriveSimulator> sim;
    try {
        sim.emplace(navmap::sim::DriveSimulator::create(req));
    } catch (const navmap::sim::SimError& e) {
        std::fprintf(stderr, "navmap-sim: %s\n", e.what());
        return 1;
    }
    const auto& route = sim->route();
    if (!cli.quiet) {
        std::fprintf(stderr, "navmap-sim: route %s (%.5f,%.5f) -> %s (%.5f,%.5f): %.0f m, %zu points, %zu maneuvers\n",
                     cli.from.c_str(), sim->fromPoint().lat_deg, sim->fromPoint().lon_deg, cli.to.c_str(),
                     sim->toPoint().lat_deg, sim->toPoint().lon_deg, route.length(), route.line.size(),
                     route.maneuvers.size());
    }
    const std::string msg = navmap::sim::setRouteMessage(route, sim->projection(), cli.route_id);
    if (!publishRoute(cli, msg)) return 1;

    std::optional<navmap::sim::CandumpWriter> log;
    std::optional<navmap::ipc::SocketCanSource> can;
    if (!openOutputs(cli, log, can)) return 1;

    StopSignals stop;
    navmap::sim::FrameGenerator gen = sim->generator();
    const SendOutcome outcome = sendFrames(cli, req.frames.start_time, gen, log, can, stop);
    if (outcome.write_failed) return 1;
    if (log) {
        if (outcome.interrupted) {
            std::fprintf(stderr, "navmap-sim: interrupted; %s not written\n", cli.out.c_str());
            return 1;
        }
        if (auto st = log->close(); !st) {
            std::fprintf(stderr, "navmap-sim: %s\n", st.message().c_str());
            return 1;
        }
    }
    printSummary(cli, req, *sim, gen, log, can.has_value(), outcome);
    return outcome.interrupted ? 1 : 0;
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"navmap-sim: simulated drive on the road graph -> navmap.dbc GNSS frames (candump log, SocketCAN)"};
    navmap::cli::setUp(app, "navmap-sim");
    SimOptions options;
    addSimOptions(app, options);
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) return *exit_status;
    return runSim(options);
}
