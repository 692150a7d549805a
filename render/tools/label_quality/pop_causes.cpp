// SPDX-License-Identifier: Apache-2.0
#include "pop_causes.h"

#include <unordered_map>

namespace navmap::render::labels {

namespace {

PopCause fromInput(InputCause c) {
    switch (c) {
        case InputCause::View: return PopCause::Edge;
        case InputCause::Tiles: return PopCause::Gone;
        case InputCause::TooSmall: return PopCause::TooSmall;
        case InputCause::Hidden:
        case InputCause::StreetRepeat: break;
    }
    return PopCause::Other;
}

}  // namespace

const char* popCauseName(PopCause cause) {
    switch (cause) {
        case PopCause::Edge: return "edge";
        case PopCause::TooSmall: return "too_small";
        case PopCause::Overlap: return "overlap";
        case PopCause::Gone: return "gone";
        case PopCause::KeepOut: return "keep_out";
        case PopCause::Other: break;
    }
    return "other";
}

PopCauses::PopCauses(DrawnMetricsParams params) : m_params(params) {}

PopCause PopCauses::inputCause(std::uint64_t id) const {
    const auto it = m_last_input.find(id);
    return it == m_last_input.end() ? PopCause::Other : fromInput(it->second);
}

PopCause PopCauses::enterCause(const PlacedLabel* p, std::uint64_t id) const {
    if (!p || p->state == LabelState::FadingOut) return PopCause::Other;
    switch (p->held_by) {
        case RemovalReason::None:  // placed at its first attempt: it just became a candidate
        case RemovalReason::Gone: return inputCause(id);
        case RemovalReason::OffScreen: return PopCause::Edge;
        case RemovalReason::Overlap: return PopCause::Overlap;
        case RemovalReason::KeepOut: return PopCause::KeepOut;
        case RemovalReason::Speed:
        case RemovalReason::Constricted: break;
    }
    return PopCause::Other;
}

PopCause PopCauses::leaveCause(const PlacedLabel* p, std::uint64_t id) const {
    if (!p || p->state != LabelState::FadingOut) return PopCause::Other;  // e.g. the SS/WS cross-fade
    switch (p->reason) {
        case RemovalReason::Gone: return inputCause(id);
        case RemovalReason::OffScreen: return PopCause::Edge;
        case RemovalReason::Overlap: return PopCause::Overlap;
        case RemovalReason::KeepOut: return PopCause::KeepOut;
        case RemovalReason::None:
        case RemovalReason::Speed:
        case RemovalReason::Constricted: break;
    }
    return PopCause::Other;
}

void PopCauses::addFrame(std::span<const DrawnLabel> drawn, std::span<const PlacedLabel> placed,
                         std::span<const LabelInputChange> changes, glm::vec2 viewport, bool measured) {
    for (const LabelInputChange& c : changes) m_last_input[c.id] = c.cause;
    if (!measured) return;

    // The visible set as DrawnLabelMetrics sees it: per id the entry with the highest opacity.
    std::unordered_map<std::uint64_t, const DrawnLabel*> best;
    for (const DrawnLabel& l : drawn) {
        auto [it, inserted] = best.try_emplace(l.id, &l);
        if (!inserted && l.opacity > it->second->opacity) it->second = &l;
    }
    std::unordered_map<std::uint64_t, const PlacedLabel*> layout;
    for (const PlacedLabel& p : placed) layout.emplace(p.id, &p);
    const auto find = [&](std::uint64_t id) {
        const auto it = layout.find(id);
        return it == layout.end() ? nullptr : it->second;
    };
    const auto interior = [&](const DrawnLabel& l) {
        if (l.kind != LabelKind::Point && l.kind != LabelKind::Area) return false;
        const float m = m_params.interior_margin_px;
        return l.anchor.x >= m && l.anchor.x <= viewport.x - m && l.anchor.y >= m && l.anchor.y <= viewport.y - m;
    };

    std::unordered_map<std::uint64_t, Seen> now;
    for (const auto& [id, l] : best) {
        if (!(l->opacity >= m_params.visible_opacity)) continue;
        const Seen s{interior(*l)};
        now.emplace(id, s);
        m_seen.insert(id);
        if (!m_started) {
            m_first.insert(id);
            ++m_f.visible_runs;
            continue;
        }
        if (m_prev.contains(id)) continue;
        const auto cause = static_cast<std::size_t>(enterCause(find(id), id));
        ++m_f.enters;
        ++m_f.visible_runs;
        ++m_f.pops[cause];
        if (s.interior_point) ++m_f.interior_point_pops[cause];
    }
    if (m_started) {
        for (const auto& [id, s] : m_prev) {
            if (now.contains(id)) continue;
            const auto cause = static_cast<std::size_t>(leaveCause(find(id), id));
            ++m_f.leaves;
            ++m_f.pops[cause];
            if (s.interior_point) ++m_f.interior_point_pops[cause];
        }
    }
    m_started = true;
    m_prev.swap(now);
}

PopCauseFigures PopCauses::summary() const {
    PopCauseFigures f = m_f;
    f.floor = 0;
    for (const std::uint64_t id : m_seen) {
        f.floor += m_first.contains(id) ? 0 : 1;
        f.floor += m_prev.contains(id) ? 0 : 1;
    }
    return f;
}

}  // namespace navmap::render::labels
