// SPDX-License-Identifier: Apache-2.0
#include "drive_trajectory.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

namespace navmap::render::tools {

namespace {

using nlohmann::json;

std::string number(double v) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.10g", v);
    return buf;
}

// A required finite number member of frame `where`.
double member(const json& frame, const char* name, const std::string& where, const std::string& source) {
    const auto it = frame.find(name);
    if (it == frame.end()) throw TrajectoryError(source + ": " + where + ": missing \"" + name + "\"");
    if (!it->is_number()) {
        throw TrajectoryError(source + ": " + where + "." + name + ": must be a number, not " + it->type_name());
    }
    const double v = it->get<double>();
    if (!std::isfinite(v)) throw TrajectoryError(source + ": " + where + "." + name + ": not a finite number");
    return v;
}

void inRange(double v, double lo, double hi, const char* name, const std::string& where, const std::string& source) {
    if (v < lo || v > hi) {
        throw TrajectoryError(source + ": " + where + "." + name + ": " + number(v) + " out of range [" + number(lo) +
                              ", " + number(hi) + "]");
    }
}

}  // namespace

DriveTrajectory parseTrajectory(std::string_view text, const std::string& source) {
    json root;
    try {
        root = json::parse(text.begin(), text.end());
    } catch (const json::exception& e) {
        // nlohmann's messages start with "[json.exception.parse_error.101] "; keep the rest.
        const std::string what = e.what();
        const auto pos = what.find("] ");
        throw TrajectoryError(source + ": invalid JSON: " + (pos == std::string::npos ? what : what.substr(pos + 2)));
    }
    if (!root.is_object())
        throw TrajectoryError(source + ": must be a JSON object with \"frames\", not " + std::string(root.type_name()));
    DriveTrajectory d;
    if (const auto fps = root.find("fps"); fps != root.end()) {
        if (!fps->is_number() || !(fps->get<double>() > 0.0) || !std::isfinite(fps->get<double>())) {
            throw TrajectoryError(source + ": fps: must be a positive number");
        }
        d.fps = fps->get<double>();
    }
    const auto frames = root.find("frames");
    if (frames == root.end()) throw TrajectoryError(source + ": missing \"frames\"");
    if (!frames->is_array())
        throw TrajectoryError(source + ": \"frames\" must be an array, not " + std::string(frames->type_name()));
    if (frames->empty()) throw TrajectoryError(source + ": \"frames\" is empty");
    d.frames.reserve(frames->size());
    for (std::size_t i = 0; i < frames->size(); ++i) {
        const json& f = (*frames)[i];
        const std::string where = "frames[" + std::to_string(i) + "]";
        if (!f.is_object()) throw TrajectoryError(source + ": " + where + ": must be an object");
        if (const auto index = f.find("i"); index != f.end()) {
            if (!index->is_number_integer() || index->get<std::int64_t>() != static_cast<std::int64_t>(i)) {
                throw TrajectoryError(source + ": " + where + ".i: " + index->dump() + " is not the frame's index " +
                                      std::to_string(i));
            }
        }
        TrajectoryPose p;
        p.t_s = member(f, "t", where, source);
        p.s_m = member(f, "s", where, source);
        p.position.lon_deg = member(f, "lon", where, source);
        p.position.lat_deg = member(f, "lat", where, source);
        const double bearing = member(f, "bearing", where, source);
        inRange(p.position.lat_deg, -90.0, 90.0, "lat", where, source);
        inRange(p.position.lon_deg, -180.0, 180.0, "lon", where, source);
        inRange(bearing, -360.0, 360.0, "bearing", where, source);
        p.bearing_deg = std::fmod(bearing + 360.0, 360.0);
        if (!d.frames.empty()) {
            const TrajectoryPose& prev = d.frames.back();
            if (!(p.t_s > prev.t_s)) {
                throw TrajectoryError(source + ": " + where + ".t: " + number(p.t_s) +
                                      " is not after the previous frame's " + number(prev.t_s));
            }
            if (p.s_m < prev.s_m) {
                throw TrajectoryError(source + ": " + where + ".s: " + number(p.s_m) +
                                      " is less than the previous frame's " + number(prev.s_m));
            }
        }
        d.frames.push_back(p);
    }
    return d;
}

DriveTrajectory loadTrajectory(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw TrajectoryError("open(" + path.string() + "): " + std::strerror(errno));
    std::ostringstream text;
    text << in.rdbuf();
    if (in.bad()) throw TrajectoryError("read(" + path.string() + "): " + std::strerror(errno));
    return parseTrajectory(text.str(), path.string());
}

}  // namespace navmap::render::tools
