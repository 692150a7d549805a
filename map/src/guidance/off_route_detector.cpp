// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/guidance/off_route_detector.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace navmap::map::guidance {

namespace {

std::string num(double v) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%g", v);
    return buf;
}

bool nonNegative(double v) { return std::isfinite(v) && v >= 0.0; }

}  // namespace

std::string OffRouteConfig::problem() const {
    if (!nonNegative(leave_distance_m)) return "leave_distance_m " + num(leave_distance_m) + " must be a distance >= 0";
    if (!nonNegative(return_distance_m))
        return "return_distance_m " + num(return_distance_m) + " must be a distance >= 0";
    if (!nonNegative(leave_time_s)) return "leave_time_s " + num(leave_time_s) + " must be a time >= 0";
    if (!nonNegative(return_time_s)) return "return_time_s " + num(return_time_s) + " must be a time >= 0";
    if (return_distance_m >= leave_distance_m) {
        return "return_distance_m " + num(return_distance_m) + " must be below leave_distance_m " +
               num(leave_distance_m);
    }
    return {};
}

OffRouteDetector::OffRouteDetector(OffRouteConfig config) : m_config(config) {
    if (const std::string p = m_config.problem(); !p.empty()) throw std::runtime_error("off-route detection: " + p);
}

void OffRouteDetector::reset() {
    m_off = false;
    m_candidate_since.reset();
    m_last_time.reset();
}

bool OffRouteDetector::update(double time_s, double distance_m) {
    if (!std::isfinite(time_s) || !std::isfinite(distance_m) || (m_last_time && time_s < *m_last_time)) {
        ++m_ignored;
        return m_off;
    }
    m_last_time = time_s;
    // A run of samples on the far side of the threshold for the opposite state; any sample on
    // the near side ends the run, so noise around one threshold never toggles the state.
    const bool beyond = m_off ? distance_m < m_config.return_distance_m : distance_m > m_config.leave_distance_m;
    if (!beyond) {
        m_candidate_since.reset();
        return m_off;
    }
    if (!m_candidate_since) m_candidate_since = time_s;
    const double hold = m_off ? m_config.return_time_s : m_config.leave_time_s;
    if (time_s - *m_candidate_since >= hold) {
        m_off = !m_off;
        m_candidate_since.reset();
    }
    return m_off;
}

}  // namespace navmap::map::guidance
