// SPDX-License-Identifier: Apache-2.0
#pragma once
// One simulated drive end to end, for navmap-sim, navmapd and tests: store -> places -> A* route
// -> speed profile -> GNSS frames. The frames can go to a candump log, to SocketCAN, or stay
// in-process (frames() / an ipc::Replayer playing them with real timing into a FrameQueue).

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "navmap/ipc/can/can_frame.h"
#include "navmap/ipc/can/dbc_database.h"
#include "navmap/ipc/can/replayer.h"
#include "navmap/map/tile_store.h"
#include "navmap/sim/drive_route.h"
#include "navmap/sim/frame_generator.h"
#include "navmap/sim/place_resolver.h"
#include "navmap/sim/speed_profile.h"

namespace navmap::sim {

struct DriveRequest {
    std::filesystem::path store;  ///< compiled tile store (navmap-compile)
    std::filesystem::path dbc;    ///< navmap.dbc
    std::string from;             ///< "lat,lon" or a place name
    std::string to;
    DriveParams drive;
    FrameOptions frames;
};

class DriveSimulator {
public:
    /// Opens the store and the DBC, resolves the places, routes and builds the profile.
    /// Throws SimError (store, DBC, unknown place, no route) with a message naming the problem.
    static DriveSimulator create(const DriveRequest& request);

    [[nodiscard]] const DriveRoute& route() const { return m_route; }
    [[nodiscard]] const SpeedProfile& profile() const { return *m_profile; }
    [[nodiscard]] map::Projection projection() const { return m_store->projection(); }
    [[nodiscard]] GeoCoordinate fromPoint() const { return m_from; }
    [[nodiscard]] GeoCoordinate toPoint() const { return m_to; }
    [[nodiscard]] const std::shared_ptr<const map::TileStore>& store() const { return m_store; }
    [[nodiscard]] const std::shared_ptr<const ipc::DbcDatabase>& dbc() const { return m_dbc; }

    /// A fresh generator over this drive (frames from the start).
    [[nodiscard]] FrameGenerator generator(const FrameOptions& options) const;
    [[nodiscard]] FrameGenerator generator() const { return generator(m_frames); }
    /// All frames of the drive in memory (about 60 frames per second of driving).
    [[nodiscard]] std::vector<ipc::CanFrame> frames() const;
    /// In-process source: a Replayer over frames() (drive it with advanceTo() or start()).
    [[nodiscard]] std::unique_ptr<ipc::Replayer> replayer(ipc::ReplayOptions options) const;

private:
    DriveSimulator() = default;
    std::shared_ptr<const map::TileStore> m_store;
    std::shared_ptr<const ipc::DbcDatabase> m_dbc;
    GeoCoordinate m_from, m_to;
    DriveRoute m_route;
    std::shared_ptr<const SpeedProfile> m_profile;
    FrameOptions m_frames;
};

}  // namespace navmap::sim
