// SPDX-License-Identifier: Apache-2.0
// The input's CAN sources behind one interface: the simulator's frames decode through the same
// DBC decoder (and SocketCAN's kernel frame codec) as a real bus to the simulated speed and yaw
// rate; a candump replay plays with its timing and counts malformed lines; SocketCAN retries a
// missing interface and says why; sim mode sets the route it drives on the control state.

#include <gtest/gtest.h>

#include <fstream>

#include "can_sources.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/replay_input.h"
#include "navmap/ipc/can/signal_map.h"
#include "navmap/ipc/can/socketcan_codec.h"
#include "navmap/ipc/can/socketcan_input.h"
#include "navmap/ipc/can/vehicle_decoder.h"
#include "navmap/sim/drive_simulator.h"
#include "navmap/sim/simulated_can_source.h"
#include "test_paths.h"

using namespace navmap;
using namespace std::chrono_literals;

namespace {

const ipc::CanTime kStart = ipc::CanTime(std::chrono::seconds(1'700'000'000));

std::filesystem::path storePath() { return test::binaryDir() / "andorra.navmap"; }
std::filesystem::path dbcPath() { return test::dataDir() / "navmap.dbc"; }

#define REQUIRE_STORE()                                                                                       \
    if (!std::filesystem::exists(storePath())) {                                                              \
        GTEST_SKIP() << "no compiled store at " << storePath() << " (build the navmap_default_store target)"; \
    }

// The decoder navmapd builds by default: the shipped navmap.dbc and its signal map.
ipc::VehicleDecoder daemonDecoder() {
    auto db = ipc::DbcDatabase::load(dbcPath());
    EXPECT_TRUE(db) << db.error().message;
    auto decoder = ipc::VehicleDecoder::create({std::make_shared<const ipc::DbcDatabase>(std::move(db).value())},
                                               ipc::SignalMap::navmapDefaults());
    EXPECT_TRUE(decoder) << decoder.error().message;
    return std::move(decoder).value();
}

std::vector<ipc::CanFrame> pollAll(ipc::CanSource& source, ipc::CanTime now) {
    std::vector<ipc::CanFrame> frames;
    source.poll(now, [&](const ipc::CanFrame& f) { frames.push_back(f); });
    return frames;
}

}  // namespace

TEST(SimulatedCanSource, ItsFramesDecodeThroughTheDaemonsDecoderToTheSimulatedSpeedAndYawRate) {
    REQUIRE_STORE();
    sim::SimulatedDriveRequest request;
    request.store = storePath();
    request.dbc = dbcPath();
    request.from = "andorra-la-vella";
    request.to = "encamp";
    sim::SimulatedCanSource simulator(request);
    ipc::CanSource& source = simulator;
    EXPECT_EQ(source.name(), "sim andorra-la-vella -> encamp");

    // The ground truth: the same drive, planned again.
    sim::DriveRequest drive;
    drive.store = request.store;
    drive.dbc = request.dbc;
    drive.from = request.from;
    drive.to = request.to;
    const sim::DriveSimulator truth = sim::DriveSimulator::create(drive);
    const sim::FrameGenerator generator = truth.generator();

    source.start(kStart);
    EXPECT_TRUE(pollAll(source, kStart - 1ms).empty()) << "nothing is due before the start";
    // The input thread polls every few milliseconds; a poll hands over a bounded burst.
    std::vector<ipc::CanFrame> frames;
    for (auto t = kStart; t <= kStart + 60s; t += 100ms) {
        for (auto& f : pollAll(source, t)) frames.push_back(f);
    }
    ASSERT_GT(frames.size(), 60u * 50u) << "a minute of NAV_Motion at 50 Hz and more";

    ipc::VehicleDecoder decoder = daemonDecoder();
    std::size_t motion = 0;
    double fastest_kmh = 0.0;
    for (const auto& f : frames) {
        ASSERT_GE(f.timestamp, kStart);
        // As on a real bus: through SocketCAN's kernel frame layout and back.
        canfd_frame kernel{};
        const std::size_t bytes = ipc::frameToKernel(f, kernel);
        const auto received = ipc::frameFromKernel(&kernel, bytes, f.timestamp);
        ASSERT_TRUE(received.has_value());
        ipc::VehicleSample sample;
        if (!decoder.decode(*received, sample)) continue;
        const auto speed = sample.get(ipc::VssSignal::Speed);
        if (!speed) continue;
        ++motion;
        const auto t_us = std::chrono::duration_cast<std::chrono::microseconds>(f.timestamp - kStart).count();
        const sim::VehicleState expected = generator.truthAt(static_cast<double>(t_us) * 1e-6);
        EXPECT_NEAR(*speed, expected.speed_mps * 3.6, 0.006) << "at " << t_us << " us";
        const auto yaw = sample.get(ipc::VssSignal::YawRate);
        ASSERT_TRUE(yaw.has_value());
        EXPECT_NEAR(*yaw, expected.yaw_rate_dps, 0.006) << "at " << t_us << " us";
        fastest_kmh = std::max(fastest_kmh, *speed);
    }
    EXPECT_GE(motion, 60u * 50u);
    EXPECT_GT(fastest_kmh, 20.0) << "the simulated car drives";
    EXPECT_EQ(decoder.counters().rejected, 0u);

    ipc::CanSourceStatus status;
    source.report(status);
    EXPECT_EQ(status.replay_time_errors, 0u);
    EXPECT_TRUE(status.error.empty()) << status.error;

    // The route it drives, in degrees, is the planned line.
    const auto& line = truth.route().line;
    ASSERT_EQ(simulator.routePoints().size(), line.size());
    const map::Projection projection = truth.projection();
    for (std::size_t i = 0; i < line.size(); i += 25) {
        const auto p = projection.forward(simulator.routePoints()[i].lat_deg, simulator.routePoints()[i].lon_deg);
        EXPECT_NEAR(p.x, line[i].position.x, 1e-6);
        EXPECT_NEAR(p.y, line[i].position.y, 1e-6);
    }
}

TEST(CanSources, SimModeSetsTheRouteItDrivesOnTheControlState) {
    REQUIRE_STORE();
    daemon::DaemonConfig config;
    config.input = daemon::InputSource::Sim;
    daemon::CanSourceSite site;
    site.store_path = storePath();
    site.data_dir = test::dataDir();
    ipc::ControlState control;
    const daemon::OpenedCanSource opened = daemon::openCanSource(config, site, control, sim::openSimulatedDrive);
    ASSERT_NE(opened.source, nullptr) << opened.error;
    EXPECT_EQ(opened.name, "sim andorra-la-vella -> encamp");
    const auto route = control.route();
    ASSERT_NE(route, nullptr);
    EXPECT_EQ(route->id, "sim");
    EXPECT_GT(route->points.size(), 10u);
}

TEST(CanSources, SimModeWithoutARoadGraphHasNoSourceAndSaysWhy) {
    daemon::DaemonConfig config;
    config.input = daemon::InputSource::Sim;
    daemon::CanSourceSite site;
    site.graph_problem = "graph section: checksum mismatch";
    ipc::ControlState control;
    const daemon::OpenedCanSource opened = daemon::openCanSource(config, site, control, sim::openSimulatedDrive);
    EXPECT_EQ(opened.source, nullptr);
    EXPECT_EQ(opened.name, "sim andorra-la-vella -> encamp");
    EXPECT_EQ(opened.error,
              "the simulator cannot plan a route: road graph unavailable: graph section: checksum mismatch");
    EXPECT_EQ(control.route(), nullptr);
}

// A program that hands the daemon no simulator (RunOptions::simulator empty) runs sim mode
// without a source and says why.
TEST(CanSources, SimModeWithoutASimulatorHasNoSourceAndSaysWhy) {
    daemon::DaemonConfig config;
    config.input = daemon::InputSource::Sim;
    ipc::ControlState control;
    const daemon::OpenedCanSource opened = daemon::openCanSource(config, daemon::CanSourceSite{}, control, {});
    EXPECT_EQ(opened.source, nullptr);
    EXPECT_EQ(opened.error, "this program has no drive simulator (input source \"sim\")");
    EXPECT_EQ(control.route(), nullptr);
}

TEST(ReplayInput, PlaysTheLogWithItsTimingAndCountsMalformedLines) {
    const auto path =
        std::filesystem::temp_directory_path() / ("navmap-replay-input-" + std::to_string(::getpid()) + ".candump");
    {
        std::ofstream out(path);
        out << "(100.000000) vcan0 6A1#1027000000003309\n"
            << "this is no candump line\n"
            << "(100.500000) vcan0 123#DEADBEEF\n";
    }
    ipc::ReplayInput replay(path, 1.0, false);
    EXPECT_EQ(replay.name(), "replay " + path.string());
    replay.start(kStart);
    const auto first = pollAll(replay, kStart + 100ms);
    ASSERT_EQ(first.size(), 1u);
    EXPECT_EQ(first[0].id, 0x6A1u);
    EXPECT_EQ(first[0].timestamp, kStart) << "restamped to the wall clock";
    const auto second = pollAll(replay, kStart + 600ms);
    ASSERT_EQ(second.size(), 1u);
    EXPECT_EQ(second[0].id, 0x123u);
    EXPECT_EQ(second[0].timestamp, kStart + 500ms);
    ipc::CanSourceStatus status;
    replay.report(status);
    EXPECT_EQ(status.replay_malformed_lines, 1u);
    EXPECT_TRUE(status.error.empty()) << status.error;
    std::filesystem::remove(path);
}

TEST(ReplayInput, AMissingLogIsAnErrorNamingIt) {
    const std::filesystem::path path = "/nonexistent/navmap/drive.candump";
    try {
        ipc::ReplayInput replay(path, 1.0, true);
        FAIL() << "opened a missing file";
    } catch (const std::runtime_error& e) {
        EXPECT_NE(std::string(e.what()).find(path.string()), std::string::npos) << e.what();
    }
}

TEST(SocketCanInput, AMissingInterfaceIsRetriedAndTheStatusSaysWhy) {
    ipc::SocketCanInput can("navmapnx0", {0x6A0, 0x6A1});
    EXPECT_EQ(can.name(), "socketcan navmapnx0");
    can.start(kStart);
    EXPECT_TRUE(pollAll(can, kStart).empty());
    ipc::CanSourceStatus status;
    can.report(status);
    EXPECT_EQ(status.can_state.rfind("retrying: ", 0), 0u) << status.can_state;
    EXPECT_NE(status.can_state.find("navmapnx0"), std::string::npos) << status.can_state;
}
