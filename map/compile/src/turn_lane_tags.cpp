// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/turn_lane_tags.h"

#include <array>
#include <charconv>
#include <optional>
#include <utility>

namespace navmap::map {

namespace {

// The values of the OSM wiki's "Key:turn" ("turn:lanes"), the ones drivers see as arrows.
// `none` and an empty value are a lane without arrows.
constexpr std::array<std::pair<std::string_view, std::uint16_t>, 11> kArrows{{
    {"left", lane_arrow::kLeft},
    {"slight_left", lane_arrow::kSlightLeft},
    {"sharp_left", lane_arrow::kSharpLeft},
    {"through", lane_arrow::kThrough},
    {"slight_right", lane_arrow::kSlightRight},
    {"right", lane_arrow::kRight},
    {"sharp_right", lane_arrow::kSharpRight},
    {"reverse", lane_arrow::kReverse},
    {"merge_to_left", lane_arrow::kMergeToLeft},
    {"merge_to_right", lane_arrow::kMergeToRight},
    {"none", 0},
}};

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

/// A lane count tag ("2"); nullopt when absent or not a whole number from 1 to kMaxTurnLanes.
std::optional<std::size_t> laneCount(const TagLookup& tags, const char* key) {
    const char* v = tags(key);
    if (v == nullptr) return std::nullopt;
    const std::string_view text = trim(v);
    std::size_t n = 0;
    const auto res = std::from_chars(text.data(), text.data() + text.size(), n);
    if (res.ec != std::errc{} || res.ptr != text.data() + text.size() || n == 0) return std::nullopt;
    return n;
}

}  // namespace

// Hand-written: the value is a small grammar of its own (`|` between lanes, `;` between the
// arrows of one lane) that no library in the tree parses; libosmium hands over the raw string.
ParsedTurnLanes parseTurnLanes(std::string_view text) {
    ParsedTurnLanes out;
    if (trim(text).empty()) return out;
    std::size_t lanes = 1;
    for (const char c : text) lanes += c == '|' ? 1 : 0;
    if (lanes > kMaxTurnLanes) {
        out.too_many = true;
        return out;
    }
    while (true) {
        const std::size_t bar = text.find('|');
        std::string_view lane = text.substr(0, bar);
        std::uint16_t arrows = 0;
        while (true) {
            const std::size_t semi = lane.find(';');
            const std::string_view value = trim(lane.substr(0, semi));
            if (!value.empty()) {
                bool known = false;
                for (const auto& [name, bit] : kArrows) {
                    if (name != value) continue;
                    arrows |= bit;
                    known = true;
                    break;
                }
                if (!known) ++out.unknown_values;
            }
            if (semi == std::string_view::npos) break;
            lane.remove_prefix(semi + 1);
        }
        out.lanes.push_back(arrows);
        if (bar == std::string_view::npos) break;
        text.remove_prefix(bar + 1);
    }
    return out;
}

DirectionalTurnLanes turnLanesFromTags(const TagLookup& tags, int oneway_direction) {
    DirectionalTurnLanes d;
    // The lanes of one tag, or nothing when it is absent or unusable (counted).
    const auto read = [&](const char* key) -> std::optional<std::vector<std::uint16_t>> {
        const char* v = tags(key);
        if (v == nullptr) return std::nullopt;
        ParsedTurnLanes p = parseTurnLanes(v);
        d.unknown_values += p.unknown_values;
        if (p.too_many) {
            ++d.dropped;
            return std::nullopt;
        }
        if (p.lanes.empty()) return std::nullopt;
        return std::move(p.lanes);
    };
    auto forward = read("turn:lanes:forward");
    auto backward = read("turn:lanes:backward");
    auto plain = read("turn:lanes");
    if (oneway_direction > 0) {
        // The only direction runs along the nodes; `turn:lanes:forward` says the same.
        d.forward = forward ? std::move(*forward) : plain.value_or(std::vector<std::uint16_t>{});
        return d;
    }
    if (oneway_direction < 0) {
        d.backward = backward ? std::move(*backward) : plain.value_or(std::vector<std::uint16_t>{});
        return d;
    }
    if (forward) d.forward = std::move(*forward);
    if (backward) d.backward = std::move(*backward);
    if (plain) {
        // A two-way road's plain `turn:lanes` names no direction: only a direction with exactly
        // as many lanes takes it.
        const std::size_t n = plain->size();
        const auto total = laneCount(tags, "lanes");
        const auto count_of = [&](const char* key) {
            const auto c = laneCount(tags, key);
            if (c) return c;
            if (total && *total == 2 * n) return std::optional<std::size_t>{n};
            return std::optional<std::size_t>{};
        };
        bool used = false;
        if (d.forward.empty() && count_of("lanes:forward") == n) {
            d.forward = *plain;
            used = true;
        }
        if (d.backward.empty() && count_of("lanes:backward") == n) {
            d.backward = *plain;
            used = true;
        }
        if (!used) ++d.dropped;
    }
    return d;
}

}  // namespace navmap::map
