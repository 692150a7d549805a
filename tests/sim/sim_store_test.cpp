// SPDX-License-Identifier: Apache-2.0
// The simulator on the compiled Andorra store: places from the store's labels, A* routes,
// generated frames decoded back onto the route, the set_route message accepted by the control
// protocol parser, and the shipped drives in data/drives.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "navmap/ipc/can/candump_reader.h"
#include "navmap/ipc/control/control_protocol.h"
#include "navmap/sim/drive_simulator.h"
#include "navmap/sim/route_message.h"
#include "navmap/sim/sim_error.h"
#include "navmap/sim/terrain_sampler.h"
#include "sim_test_util.h"
#include "test_paths.h"

namespace navmap::sim {
namespace {

std::filesystem::path storePath() { return navmap::test::binaryDir() / "andorra.navmap"; }

DriveRequest request(const std::string& from, const std::string& to) {
    DriveRequest r;
    r.store = storePath();
    r.dbc = NAVMAP_IPC_DEFAULT_DBC;
    r.from = from;
    r.to = to;
    return r;
}

class SimStore : public ::testing::Test {
protected:
    void SetUp() override {
        if (!std::filesystem::exists(storePath()))
            GTEST_SKIP() << "no compiled store at " << storePath() << " (build navmap_default_store)";
    }
};

TEST_F(SimStore, ParishTownsComeFromTheStoresPlaceLabels) {
    const auto store = map::TileStore::open(storePath());
    const PlaceResolver r = PlaceResolver::fromStore(*store);
    const PlaceResolver builtin;
    std::size_t from_store = 0;
    for (const auto& p : r.places()) from_store += p.builtin ? 0 : 1;
    EXPECT_GT(from_store, 20U);
    for (const char* name :
         {"Andorra la Vella", "Escaldes", "Encamp", "Sant Julià de Lòria", "La Massana", "Ordino", "Canillo"}) {
        auto got = r.resolve(name);
        ASSERT_TRUE(got.ok()) << name;
        // The store's label is used (it is listed first), close to the table's town centre.
        bool found = false;
        for (const auto& p : r.places()) {
            if (!p.builtin && p.point == got.value()) found = true;
        }
        EXPECT_TRUE(found) << name << " resolved from the built-in table, not the store";
        const auto table = builtin.resolve(name).value();
        const map::Projection proj = store->projection();
        const auto a = proj.forward(got.value().lat_deg, got.value().lon_deg);
        const auto b = proj.forward(table.lat_deg, table.lon_deg);
        EXPECT_LT(std::hypot(a.x - b.x, a.y - b.y), 1500.0) << name;
    }
}

TEST_F(SimStore, RoutesAndorraLaVellaToEncampAndDecodesBackOntoTheRoute) {
    DriveRequest req = request("Andorra la Vella", "Encamp");
    req.frames.noise_m = 3.0;
    const DriveSimulator sim = DriveSimulator::create(req);
    const DriveRoute& route = sim.route();
    EXPECT_GT(route.length(), 5000.0);
    EXPECT_LT(route.length(), 9000.0);
    EXPECT_GE(route.maneuvers.size(), 3U);
    EXPECT_EQ(route.maneuvers.front().type, "depart");
    EXPECT_EQ(route.maneuvers.back().type, "arrive");
    // Realistic: slower than the A* estimate at the legal speeds (curves, acceleration), not absurdly.
    EXPECT_GT(sim.profile().duration(), route.graph_duration_s);
    EXPECT_LT(sim.profile().duration(), 2.0 * route.graph_duration_s);

    FrameGenerator gen = sim.generator();
    ipc::VehicleDecoder dec = test::navmapDecoder();
    const map::Projection proj = sim.projection();
    ipc::CanFrame f;
    std::size_t positions = 0, far = 0;
    double max_err = 0.0, max_alt = 0.0, min_alt = 1e9;
    while (gen.next(f)) {
        ipc::VehicleSample s;
        dec.decode(f, s);
        const double t = std::chrono::duration<double>(f.timestamp - req.frames.start_time).count();
        const VehicleState truth = gen.truthAt(t);
        if (s.get(ipc::VssSignal::Latitude)) {
            ++positions;
            const auto p = proj.forward(*s.get(ipc::VssSignal::Latitude), *s.get(ipc::VssSignal::Longitude));
            const double err = test::distanceToLine(route.line, p);
            max_err = std::max(max_err, err);
            far += err > 2.0 * req.frames.noise_m ? 1 : 0;
        }
        if (s.get(ipc::VssSignal::Speed)) {
            // Speeds respect the limits (legal speed and curve speed) of where the car is.
            EXPECT_LE(*s.get(ipc::VssSignal::Speed), sim.profile().limitAt(truth.measure_m) * 3.6 + 0.01);
            EXPECT_LE(*s.get(ipc::VssSignal::Speed), 90.0 + 0.01);
        }
        if (s.get(ipc::VssSignal::Altitude)) {
            max_alt = std::max(max_alt, *s.get(ipc::VssSignal::Altitude));
            min_alt = std::min(min_alt, *s.get(ipc::VssSignal::Altitude));
        }
    }
    EXPECT_GT(positions, 3000U);
    EXPECT_LT(max_err, 6.0 * req.frames.noise_m);
    EXPECT_LT(static_cast<double>(far),
              0.1 * static_cast<double>(positions));  // |N(0,s^2)| in 2D: P(r > 2s) = 13.5 %, less off-line
    EXPECT_EQ(dec.counters().rejected, 0U);
    EXPECT_EQ(dec.counters().counter_gaps, 0U);
    // Andorra la Vella lies at about 1020 m, Encamp at about 1260 m (SRTM terrain).
    EXPECT_GT(min_alt, 950.0);
    EXPECT_LT(max_alt, 1400.0);
    EXPECT_GT(max_alt - min_alt, 150.0);
}

TEST_F(SimStore, SetRouteMessageIsAcceptedByTheControlProtocol) {
    const DriveSimulator sim = DriveSimulator::create(request("les Escaldes", "Ordino"));
    const std::string line = setRouteMessage(sim.route(), sim.projection(), "r1");
    const ipc::ControlParse parsed = ipc::parseControlLine(line);
    ASSERT_TRUE(parsed.command.has_value()) << parsed.error;
    const auto* set = std::get_if<ipc::SetRouteCommand>(&parsed.command->body);
    ASSERT_NE(set, nullptr);
    EXPECT_EQ(set->route_id, "r1");
    ASSERT_EQ(set->points.size(), sim.route().line.size());
    double lat = 0, lon = 0;
    sim.projection().reverse(sim.route().line.back().position, lat, lon);
    EXPECT_NEAR(set->points.back().lat_deg, lat, 1e-7);
    EXPECT_NEAR(set->points.back().lon_deg, lon, 1e-7);
    ASSERT_EQ(set->maneuvers.size(), sim.route().maneuvers.size());
    EXPECT_EQ(set->maneuvers.front().type, ipc::ManeuverType::Depart);
    EXPECT_EQ(set->maneuvers.back().type, ipc::ManeuverType::Arrive);
    EXPECT_TRUE(replyIsOk(ipc::controlOkReply("set_route", std::string("r1"))));
    EXPECT_FALSE(replyIsOk(ipc::controlErrorReply("set_route", std::string("r1"), "bad")));
    EXPECT_FALSE(replyIsOk("{\"ok\":tru"));
}

TEST_F(SimStore, InProcessReplayerPlaysTheDrive) {
    DriveRequest req = request("Andorra la Vella", "les Escaldes");
    req.frames.max_duration_s = 20.0;
    const DriveSimulator sim = DriveSimulator::create(req);
    auto replayer = sim.replayer(ipc::ReplayOptions{1.0, false, true});
    const ipc::CanTime t0 = ipc::CanTime(std::chrono::seconds(1700000000));
    replayer->reset(t0);
    std::size_t n = 0;
    replayer->advanceTo(t0 + std::chrono::seconds(10), [&](const ipc::CanFrame&) { ++n; });
    EXPECT_NEAR(static_cast<double>(n), 10 * 61 + 3, 3.0);
    replayer->advanceTo(t0 + std::chrono::seconds(30), [&](const ipc::CanFrame&) { ++n; });
    EXPECT_TRUE(replayer->finished());
    EXPECT_EQ(n, sim.frames().size());
}

TEST_F(SimStore, SetupErrorsNameTheProblem) {
    try {
        (void)DriveSimulator::create(request("Atlantis", "Encamp"));
        FAIL() << "no exception";
    } catch (const SimError& e) {
        EXPECT_EQ(std::string(e.what()).rfind("--from: unknown place 'Atlantis'", 0), 0U) << e.what();
    }
    try {
        DriveRequest r = request("Encamp", "Encamp");
        (void)DriveSimulator::create(r);
        FAIL() << "no exception";
    } catch (const SimError& e) {
        EXPECT_NE(std::string(e.what()).find("same junction"), std::string::npos) << e.what();
    }
    try {
        DriveRequest r = request("Encamp", "Ordino");
        r.store = "/nonexistent.navmap";
        (void)DriveSimulator::create(r);
        FAIL() << "no exception";
    } catch (const SimError& e) {
        EXPECT_NE(std::string(e.what()).find("/nonexistent.navmap"), std::string::npos) << e.what();
    }
}

TEST_F(SimStore, TerrainSamplerFollowsTheDem) {
    auto store = map::TileStore::open(storePath());
    TerrainSampler t(store);
    const map::Projection proj = store->projection();
    EXPECT_NEAR(t.heightAt(proj.forward(42.5075, 1.5218)), 1050.0, 120.0);  // Andorra la Vella
    EXPECT_EQ(t.heightAt({1e7, 1e7}), 0.0);                                 // outside the store
}

// The drives shipped in data/drives (see its README): every line parses, rates are right, the
// clean drives decode without a single rejected value, consecutive fixes agree with the speed.
struct ShippedDrive {
    const char* file;
    bool faults;
};

class ShippedDrives : public ::testing::TestWithParam<ShippedDrive> {};

TEST_P(ShippedDrives, ParseAndDecodeCleanly) {
    const auto path = navmap::test::dataDir() / "drives" / GetParam().file;
    ASSERT_TRUE(std::filesystem::exists(path)) << path;
    auto log = ipc::loadCandumpFile(path);
    ASSERT_TRUE(log.ok()) << log.error().message;
    EXPECT_EQ(log.value().counters.malformed, 0U) << (log.value().errors.empty() ? "" : log.value().errors[0].message);
    EXPECT_GT(log.value().counters.frames, 1000U);
    ipc::VehicleDecoder dec = test::navmapDecoder();
    std::size_t positions = 0, motions = 0;
    std::optional<std::pair<double, double>> last;  // lat, lon
    ipc::CanTime last_t{};
    double speed_kmh = 0.0;
    std::size_t inconsistent = 0;
    const map::Projection proj = test::andorraProjection();
    for (const auto& rec : log.value().records) {
        ipc::VehicleSample s;
        dec.decode(rec.frame, s);
        if (s.get(ipc::VssSignal::Speed)) {
            ++motions;
            speed_kmh = *s.get(ipc::VssSignal::Speed);
        }
        if (s.get(ipc::VssSignal::Latitude) && s.get(ipc::VssSignal::Longitude)) {
            const double lat = *s.get(ipc::VssSignal::Latitude);
            const double lon = *s.get(ipc::VssSignal::Longitude);
            if (!GetParam().faults) {
                EXPECT_GT(lat, 42.42);
                EXPECT_LT(lat, 42.66);
                EXPECT_GT(lon, 1.40);
                EXPECT_LT(lon, 1.79);
            }
            if (last) {
                const auto a = proj.forward(last->first, last->second);
                const auto b = proj.forward(lat, lon);
                const double dt = std::chrono::duration<double>(rec.frame.timestamp - last_t).count();
                // The step between fixes matches the speed (noise of a few metres allowed).
                if (std::hypot(b.x - a.x, b.y - a.y) > speed_kmh / 3.6 * dt + 20.0) ++inconsistent;
            }
            last = {lat, lon};
            last_t = rec.frame.timestamp;
            ++positions;
        }
    }
    const double seconds = std::chrono::duration<double>(log.value().records.back().frame.timestamp -
                                                         log.value().records.front().frame.timestamp)
                               .count();
    EXPECT_NEAR(static_cast<double>(motions), seconds * 50, seconds * 0.5 + 2);
    if (GetParam().faults) {
        EXPECT_GT(dec.counters().rejected, 0U);
        EXPECT_GT(dec.counters().short_frames, 0U);
    } else {
        EXPECT_NEAR(static_cast<double>(positions), seconds * 10, seconds * 0.2 + 2);
        EXPECT_EQ(dec.counters().rejected, 0U);
        EXPECT_EQ(dec.counters().counter_gaps, 0U);
        EXPECT_EQ(inconsistent, 0U);
    }
}

INSTANTIATE_TEST_SUITE_P(Data, ShippedDrives,
                         ::testing::Values(ShippedDrive{"andorra_la_vella-encamp.candump", false},
                                           ShippedDrive{"escaldes-ordino.candump", false},
                                           ShippedDrive{"short-faults.candump", true}),
                         [](const auto& param_info) {
                             std::string n = param_info.param.file;
                             n = n.substr(0, n.find('.'));
                             for (char& c : n) c = std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
                             return n;
                         });

}  // namespace
}  // namespace navmap::sim
