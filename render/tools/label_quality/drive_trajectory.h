// SPDX-License-Identifier: Apache-2.0
#pragma once
// A recorded drive as per-frame vehicle poses (data/drives/*-trajectory.json): what the label
// quality tool replays frame by frame, the same poses other renderers were measured on.
//
// File: one JSON object with "frames": [{"t": s, "s": m, "lon": deg, "lat": deg, "bearing": deg}, ...]
// (optional "i" = the frame's index, optional top-level "fps"); other members are ignored.
#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/common/geo_coordinate.h"

namespace navmap::render::tools {

/// One frame's pose.
struct TrajectoryPose {
    double t_s = 0.0;          ///< time since the first frame
    double s_m = 0.0;          ///< distance driven along the route
    GeoCoordinate position;    ///< WGS84 degrees
    double bearing_deg = 0.0;  ///< heading, clockwise from true north, in [0, 360)
};

struct DriveTrajectory {
    std::vector<TrajectoryPose> frames;  ///< at least one; t strictly and s never decreasing
    double fps = 0.0;                    ///< the file's "fps", or 0 when it has none
};

/// A file that cannot be read or is not a trajectory; the message names the file and the problem,
/// e.g. "drive.json: frames[12].lat: 95 out of range [-90, 90]".
class TrajectoryError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

/// Parses trajectory JSON text; `source` names it in errors. Throws TrajectoryError.
DriveTrajectory parseTrajectory(std::string_view text, const std::string& source);
/// Reads and parses a file. Throws TrajectoryError.
DriveTrajectory loadTrajectory(const std::filesystem::path& path);

}  // namespace navmap::render::tools
