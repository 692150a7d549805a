// SPDX-License-Identifier: Apache-2.0
#include "navmap/sim/place_resolver.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <unordered_set>

namespace navmap::sim {

namespace {

// The seven parish towns of Andorra (approximate centres), used when the store has no matching
// place label (another store, or a name OSM spells differently).
struct BuiltinPlace {
    const char* name;
    GeoCoordinate point;
};
constexpr BuiltinPlace kBuiltin[] = {
    {"Andorra la Vella", {42.5075, 1.5218}},
    {"Escaldes-Engordany", {42.5097, 1.5390}},
    {"les Escaldes", {42.5097, 1.5390}},
    {"Encamp", {42.5347, 1.5801}},
    {"Sant Julià de Lòria", {42.4637, 1.4913}},
    {"La Massana", {42.5450, 1.5148}},
    {"Ordino", {42.5562, 1.5331}},
    {"Canillo", {42.5676, 1.5976}},
};

// ASCII folding of U+00C0..U+00FF (UTF-8 C3 80..C3 BF).
constexpr char kFoldC3[] = "aaaaaaaceeeeiiiidnooooo ouuuuytsaaaaaaaceeeeiiiidnooooo ouuuuyty";

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

std::optional<double> parseDouble(std::string_view s) {
    s = trim(s);
    if (!s.empty() && s.front() == '+') s.remove_prefix(1);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
    if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v)) return std::nullopt;
    return v;
}

bool startsWithWords(const std::string& key, const std::string& prefix) {
    return key.size() > prefix.size() && key.compare(0, prefix.size(), prefix) == 0 && key[prefix.size()] == ' ';
}

}  // namespace

std::string PlaceResolver::normalize(std::string_view name) {
    std::string folded;
    for (std::size_t i = 0; i < name.size(); ++i) {
        const auto c = static_cast<unsigned char>(name[i]);
        if (c < 0x80) {
            folded.push_back(std::isalnum(c) != 0 ? static_cast<char>(std::tolower(c)) : ' ');
        } else if (c == 0xC3 && i + 1 < name.size() && (static_cast<unsigned char>(name[i + 1]) & 0xC0) == 0x80) {
            folded.push_back(kFoldC3[static_cast<unsigned char>(name[i + 1]) - 0x80]);
            ++i;
        } else if (c >= 0xC0) {
            folded.push_back(' ');  // other letters and marks (e.g. the Catalan middle dot) separate words
        }
        // continuation bytes of skipped sequences are dropped
    }
    std::vector<std::string> words;
    std::string word;
    for (char c : folded + " ") {
        if (c == ' ') {
            if (!word.empty()) words.push_back(std::move(word));
            word.clear();
        } else {
            word.push_back(c);
        }
    }
    static const std::unordered_set<std::string> kArticles{"el", "la", "les", "l", "els", "the"};
    std::size_t first = 0;
    while (words.size() - first > 1 && kArticles.count(words[first]) != 0) ++first;
    std::string out;
    for (std::size_t i = first; i < words.size(); ++i) {
        if (!out.empty()) out.push_back(' ');
        out += words[i];
    }
    return out;
}

std::optional<ipc::Result<GeoCoordinate>> PlaceResolver::parseLatLon(std::string_view text) {
    const auto comma = text.find(',');
    if (comma == std::string_view::npos || text.find(',', comma + 1) != std::string_view::npos) return std::nullopt;
    const auto lat = parseDouble(text.substr(0, comma));
    const auto lon = parseDouble(text.substr(comma + 1));
    if (!lat || !lon) return std::nullopt;
    if (std::abs(*lat) > 90.0) {
        return ipc::Result<GeoCoordinate>(ipc::Error{"latitude " + std::to_string(*lat) + " is outside [-90, 90]"});
    }
    if (std::abs(*lon) > 180.0) {
        return ipc::Result<GeoCoordinate>(ipc::Error{"longitude " + std::to_string(*lon) + " is outside [-180, 180]"});
    }
    return ipc::Result<GeoCoordinate>(GeoCoordinate{*lat, *lon});
}

PlaceResolver::PlaceResolver() {
    for (const BuiltinPlace& b : kBuiltin) m_places.push_back({b.name, b.point, 0.0f, true});
}

PlaceResolver PlaceResolver::fromStore(const map::TileStore& store) {
    PlaceResolver r;
    std::vector<NamedPlace> found;
    std::unordered_set<std::int64_t> seen;
    const map::Projection proj = store.projection();
    // Places down to suburbs live in tiles of 8 km and coarser (docs/tile-store.md).
    const int last = store.scheme().levelForTileSize(8000.0);
    for (const map::TileId id : store.tileIds()) {
        if (id.level > last) continue;
        map::TileStore::LoadResult status;
        const auto tile = store.loadAlone(id, status);  // labels only: not the heights beyond its edges
        if (!tile) continue;
        for (const map::Label& l : tile->labels) {
            if (l.kind != map::LabelKind::Place || l.name.empty() || !seen.insert(l.osm_id).second) continue;
            NamedPlace p;
            p.name = l.name;
            p.importance = l.importance;
            proj.reverse({tile->origin_x + l.anchor.x, tile->origin_y + l.anchor.y}, p.point.lat_deg, p.point.lon_deg);
            found.push_back(std::move(p));
        }
    }
    std::stable_sort(found.begin(), found.end(),
                     [](const NamedPlace& a, const NamedPlace& b) { return a.importance > b.importance; });
    found.insert(found.end(), r.m_places.begin(), r.m_places.end());
    r.m_places = std::move(found);
    return r;
}

ipc::Result<GeoCoordinate> PlaceResolver::resolve(std::string_view text) const {
    if (auto ll = parseLatLon(text)) return *ll;
    const std::string key = normalize(text);
    if (key.empty()) return ipc::Error{"empty place name '" + std::string(text) + "'"};
    // Exact name first (store labels by importance, then the table), then a name that starts with
    // the given words ("Escaldes" -> "Escaldes-Engordany").
    for (const NamedPlace& p : m_places) {
        if (normalize(p.name) == key) return p.point;
    }
    for (const NamedPlace& p : m_places) {
        if (startsWithWords(normalize(p.name), key)) return p.point;
    }
    std::string known;
    for (const BuiltinPlace& b : kBuiltin) known += (known.empty() ? "" : ", ") + std::string(b.name);
    return ipc::Error{"unknown place '" + std::string(text) + "' (give \"lat,lon\" or a place name such as " + known +
                      ")"};
}

}  // namespace navmap::sim
