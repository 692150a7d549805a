// SPDX-License-Identifier: Apache-2.0
#include "street_bar_hold.h"

#include <cmath>

namespace navmap::daemon {

const std::optional<render::StreetBar>& StreetBarHold::update(double t_s,
                                                              const std::optional<render::StreetBar>& matched) {
    // A road without a name or ref is no street to show.
    std::optional<render::StreetBar> street = matched;
    if (street && street->name.empty() && street->ref.empty()) street.reset();
    if (!std::isfinite(t_s)) return m_shown;  // no time to measure the hold by: nothing changes
    if (!m_started || t_s < m_last_s || street != m_candidate) {
        m_candidate = std::move(street);
        m_since_s = t_s;
    }
    m_started = true;
    m_last_s = t_s;
    if (m_candidate != m_shown && t_s - m_since_s >= m_hold_s) m_shown = m_candidate;
    return m_shown;
}

}  // namespace navmap::daemon
