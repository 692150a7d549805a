// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/drive_simulator.h"

#include "navmap/map/store_info.h"
#include "navmap/sim/sim_error.h"
#include "navmap/sim/terrain_sampler.h"

namespace navmap::sim {

DriveSimulator DriveSimulator::create(const DriveRequest& request) {
    DriveSimulator s;
    try {
        s.m_store = map::TileStore::open(request.store);
    } catch (const map::StoreError& e) {
        throw SimError(e.what());
    }
    auto dbc = ipc::DbcDatabase::load(request.dbc, ipc::DbcDatabase::Mode::Strict);
    if (!dbc) throw SimError(dbc.error().message);
    s.m_dbc = std::make_shared<const ipc::DbcDatabase>(std::move(dbc).value());

    const PlaceResolver places = PlaceResolver::fromStore(*s.m_store);
    auto from = places.resolve(request.from);
    if (!from) throw SimError("--from: " + from.error().message);
    auto to = places.resolve(request.to);
    if (!to) throw SimError("--to: " + to.error().message);
    s.m_from = from.value();
    s.m_to = to.value();

    map::RoadGraph graph;
    try {
        graph = s.m_store->loadGraph();
    } catch (const map::StoreError& e) {
        throw SimError(e.what());
    }
    const map::Projection proj = s.m_store->projection();
    const map::RoutePlan plan = map::planRoute(graph, proj.forward(s.m_from.lat_deg, s.m_from.lon_deg),
                                               proj.forward(s.m_to.lat_deg, s.m_to.lon_deg));
    if (!plan.ok()) throw SimError(request.from + " -> " + request.to + ": " + plan.problem);
    s.m_route = driveRouteFromGraph(graph, *plan.route);
    if (s.m_route.line.size() < 2) throw SimError(request.from + " -> " + request.to + ": the route has no length");
    // Street names for the maneuvers come from the tiles the route crosses (the graph keeps way ids).
    std::vector<map::PlanarPoint> points;
    points.reserve(s.m_route.line.size());
    for (const map::RoutePoint& p : s.m_route.line) points.push_back(p.position);
    const auto names = map::guidance::WayNames::alongRoute(*s.m_store, points);
    s.m_route.maneuvers = graphManeuvers(graph, s.m_route.line, &names);
    s.m_profile = std::make_shared<const SpeedProfile>(SpeedProfile::build(s.m_route, request.drive));
    s.m_frames = request.frames;
    // Validate the frame options once, at setup.
    auto probe = FrameGenerator::create(s.m_dbc, s.m_profile, proj, s.m_frames);
    if (!probe) throw SimError(probe.error().message);
    return s;
}

FrameGenerator DriveSimulator::generator(const FrameOptions& options) const {
    auto sampler = std::make_shared<TerrainSampler>(m_store);
    auto g = FrameGenerator::create(m_dbc, m_profile, m_store->projection(), options,
                                    [sampler](map::PlanarPoint p) { return sampler->heightAt(p); });
    if (!g) throw SimError(g.error().message);
    return std::move(g).value();
}

std::vector<ipc::CanFrame> DriveSimulator::frames() const {
    FrameGenerator g = generator();
    std::vector<ipc::CanFrame> out;
    ipc::CanFrame f;
    while (g.next(f)) out.push_back(f);
    return out;
}

std::unique_ptr<ipc::Replayer> DriveSimulator::replayer(ipc::ReplayOptions options) const {
    return std::make_unique<ipc::Replayer>(frames(), options);
}

}  // namespace navmap::sim
