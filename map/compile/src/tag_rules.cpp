// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/tag_rules.h"

#include <array>
#include <charconv>
#include <cstring>
#include <string>
#include <utility>

namespace navmap::map {

namespace {

bool eq(const char* a, std::string_view b) { return a != nullptr && std::string_view(a) == b; }

std::string_view trim(std::string_view s) {
    while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
    while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
    return s;
}

/// Leading decimal number (comma accepted as decimal separator); rest returned in `rest`.
std::optional<double> leadingNumber(std::string_view s, std::string_view& rest) {
    std::string buf;
    std::size_t i = 0;
    bool digits = false;
    if (i < s.size() && (s[i] == '-' || s[i] == '+')) buf.push_back(s[i++]);
    for (; i < s.size(); ++i) {
        const char c = s[i];
        if (c >= '0' && c <= '9') {
            buf.push_back(c);
            digits = true;
        } else if (c == '.' || c == ',') {
            buf.push_back('.');
        } else {
            break;
        }
    }
    if (!digits) return std::nullopt;
    double v = 0;
    const auto res = std::from_chars(buf.data(), buf.data() + buf.size(), v);
    if (res.ec != std::errc{}) return std::nullopt;
    rest = trim(s.substr(i));
    return v;
}

std::optional<float> levels(const char* text) {
    if (text == nullptr) return std::nullopt;
    std::string_view rest;
    const auto v = leadingNumber(trim(text), rest);
    if (!v || *v < 0 || *v > 200) return std::nullopt;
    return static_cast<float>(*v);
}

}  // namespace

std::optional<float> parseLength(std::string_view text) {
    text = trim(text);
    std::string_view rest;
    const auto v = leadingNumber(text, rest);
    if (!v || *v < 0) return std::nullopt;
    if (rest.empty() || rest == "m" || rest == "meter" || rest == "metre" || rest == "meters" || rest == "metres") {
        return static_cast<float>(*v);
    }
    if (rest == "ft" || rest == "feet") return static_cast<float>(*v * 0.3048);
    if (rest.front() == '\'') {  // 10'6"
        rest.remove_prefix(1);
        double inches = 0;
        std::string_view tail;
        if (!rest.empty()) {
            const auto in = leadingNumber(rest, tail);
            if (!in || (tail != "\"" && !tail.empty())) return std::nullopt;
            inches = *in;
        }
        return static_cast<float>(*v * 0.3048 + inches * 0.0254);
    }
    if (rest == "km") return static_cast<float>(*v * 1000.0);
    return std::nullopt;
}

std::optional<float> parseMaxspeedKmh(std::string_view text) {
    text = trim(text);
    std::string_view rest;
    const auto v = leadingNumber(text, rest);
    if (!v || *v <= 0 || *v > 400) return std::nullopt;
    if (rest.empty() || rest == "km/h" || rest == "kmh" || rest == "kph") return static_cast<float>(*v);
    if (rest == "mph") return static_cast<float>(*v * 1.609344);
    if (rest == "knots") return static_cast<float>(*v * 1.852);
    return std::nullopt;
}

float buildingHeight(const TagLookup& tags, float default_m) {
    if (const char* h = tags("height")) {
        if (auto v = parseLength(h); v && *v > 0 && *v < 1000) return *v;
    }
    if (auto l = levels(tags("building:levels"))) {
        float roof = 0;
        if (auto r = levels(tags("roof:levels"))) roof = *r * 1.5f;
        if (*l > 0) return *l * 3.0f + roof;
    }
    return default_m;
}

float buildingMinHeight(const TagLookup& tags) {
    if (const char* h = tags("min_height")) {
        if (auto v = parseLength(h); v && *v < 1000) return *v;
    }
    if (auto l = levels(tags("building:min_level"))) return *l * 3.0f;
    return 0.0f;
}

int onewayDirection(const TagLookup& tags) {
    const char* ow = tags("oneway");
    if (eq(ow, "yes") || eq(ow, "1") || eq(ow, "true")) return 1;
    if (eq(ow, "-1") || eq(ow, "reverse")) return -1;
    if (eq(ow, "no") || eq(ow, "0") || eq(ow, "false") || eq(ow, "reversible") || eq(ow, "alternating")) return 0;
    const char* hw = tags("highway");
    if (eq(hw, "motorway") || eq(hw, "motorway_link")) return 1;
    const char* junction = tags("junction");
    if (eq(junction, "roundabout") || eq(junction, "circular")) return 1;
    return 0;
}

namespace {

template <std::size_t N>
std::optional<AreaClass> lookupKind(const std::array<std::pair<std::string_view, AreaClass>, N>& table,
                                    const char* value) {
    if (value == nullptr) return std::nullopt;
    for (const auto& [k, c] : table) {
        if (k == value) return c;
    }
    return std::nullopt;
}

}  // namespace

// The Shortbread 1.0 schema's area layers, in the order a feature is tested against them
// (docs/tile-store.md, "Area classes", has the table and the reasons). A tag combination no
// layer classifies is no area: nothing is drawn for it as land cover.
std::optional<AreaClass> areaClassFromTags(const TagLookup& tags) {
    using A = AreaClass;
    // Boundaries (administrative, protected areas, a mountain range or a region drawn as a
    // boundary relation) and place polygons (regions, islands, archipelagos) are lines and
    // labels, never areas, whatever else they are tagged with.
    if (eq(tags("type"), "boundary") || tags("boundary") != nullptr || tags("place") != nullptr) return std::nullopt;
    // pier_polygons: drawn over the water they stand in.
    static constexpr std::array<std::pair<std::string_view, A>, 3> kPiers{
        {{"pier", A::Pier}, {"breakwater", A::Pier}, {"groyne", A::Pier}}};
    if (const auto c = lookupKind(kPiers, tags("man_made"))) return c;
    // Coastlines are lines with the water on their right, not areas: the compiler assembles
    // land and sea from them (coastline.h), also where a closed one (an island) is tagged so.
    const char* natural = eq(tags("natural"), "coastline") ? nullptr : tags("natural");
    // water_polygons: natural=water whatever its water=* (lake, river, reservoir, basin, lock,
    // harbour, ...), riverbanks and docks, reservoirs and basins; glaciers.
    if (eq(natural, "water")) return A::Water;
    if (eq(natural, "glacier")) return A::Glacier;
    if (eq(tags("waterway"), "riverbank") || eq(tags("waterway"), "dock")) return A::Water;
    if (eq(tags("landuse"), "reservoir") || eq(tags("landuse"), "basin")) return A::Water;
    // Marinas and harbours (navmap's addition; Shortbread has them as POIs only): a tint over the
    // basin and the quays, never an opaque fill.
    if (eq(tags("leisure"), "marina") || eq(tags("landuse"), "harbour") || eq(tags("landuse"), "port"))
        return A::Harbour;
    // land, by natural=*, then landuse=*, then leisure=*, then amenity=grave_yard.
    static constexpr std::array<std::pair<std::string_view, A>, 10> kNatural{{{"wood", A::Forest},
                                                                              {"scrub", A::Scrub},
                                                                              {"heath", A::Scrub},
                                                                              {"grassland", A::Grass},
                                                                              {"wetland", A::Wetland},
                                                                              {"bare_rock", A::Rock},
                                                                              {"scree", A::Rock},
                                                                              {"shingle", A::Rock},
                                                                              {"sand", A::Rock},
                                                                              {"beach", A::Rock}}};
    if (const auto c = lookupKind(kNatural, natural)) return c;
    // land kinds, and the sites kinds navmap draws (military, construction).
    static constexpr std::array<std::pair<std::string_view, A>, 24> kLanduse{{{"forest", A::Forest},
                                                                              {"grass", A::Grass},
                                                                              {"meadow", A::Grass},
                                                                              {"village_green", A::Grass},
                                                                              {"greenfield", A::Grass},
                                                                              {"farmland", A::Farmland},
                                                                              {"farmyard", A::Farmland},
                                                                              {"orchard", A::Farmland},
                                                                              {"vineyard", A::Farmland},
                                                                              {"allotments", A::Farmland},
                                                                              {"plant_nursery", A::Farmland},
                                                                              {"residential", A::Residential},
                                                                              {"commercial", A::Commercial},
                                                                              {"retail", A::Commercial},
                                                                              {"industrial", A::Industrial},
                                                                              {"railway", A::Industrial},
                                                                              {"quarry", A::Industrial},
                                                                              {"landfill", A::Industrial},
                                                                              {"brownfield", A::Industrial},
                                                                              {"garages", A::Industrial},
                                                                              {"construction", A::Industrial},
                                                                              {"recreation_ground", A::Park},
                                                                              {"cemetery", A::Cemetery},
                                                                              {"military", A::Military}}};
    if (const auto c = lookupKind(kLanduse, tags("landuse"))) return c;
    static constexpr std::array<std::pair<std::string_view, A>, 9> kLeisure{{{"park", A::Park},
                                                                             {"garden", A::Park},
                                                                             {"dog_park", A::Park},
                                                                             {"golf_course", A::Sport},
                                                                             {"playground", A::Sport},
                                                                             {"pitch", A::Sport},
                                                                             {"sports_centre", A::Sport},
                                                                             {"stadium", A::Sport},
                                                                             {"track", A::Sport}}};
    if (const auto c = lookupKind(kLeisure, tags("leisure"))) return c;
    if (eq(tags("amenity"), "grave_yard")) return A::Cemetery;
    return std::nullopt;
}

std::optional<PlaceClass> areaLabelClassFromTags(const TagLookup& tags) {
    if (const char* p = tags("place")) return placeClassFromTag(p);
    // Named natural features that are no areas (Shortbread has no layer for them): a label at
    // the polygon's barycenter, as a locality.
    static constexpr std::array<std::string_view, 6> kNamedNatural{"bay",  "strait",         "peninsula",
                                                                   "cape", "mountain_range", "valley"};
    if (const char* n = tags("natural")) {
        for (const auto k : kNamedNatural) {
            if (k == n) return PlaceClass::Locality;
        }
    }
    return std::nullopt;
}

std::optional<PlaceClass> placeClassFromTag(std::string_view p) {
    using P = PlaceClass;
    static constexpr std::array<std::pair<std::string_view, P>, 14> kPlaces{{{"country", P::Country},
                                                                             {"state", P::State},
                                                                             {"region", P::State},
                                                                             {"city", P::City},
                                                                             {"town", P::Town},
                                                                             {"village", P::Village},
                                                                             {"suburb", P::Suburb},
                                                                             {"quarter", P::Suburb},
                                                                             {"hamlet", P::Hamlet},
                                                                             {"neighbourhood", P::Neighbourhood},
                                                                             {"locality", P::Locality},
                                                                             {"isolated_dwelling", P::IsolatedDwelling},
                                                                             {"farm", P::IsolatedDwelling},
                                                                             {"island", P::Island}}};
    for (const auto& [k, c] : kPlaces) {
        if (k == p) return c;
    }
    if (p.empty()) return std::nullopt;
    return P::Other;
}

std::optional<PoiClass> poiClassFromTags(const TagLookup& tags) {
    if (eq(tags("natural"), "peak") || eq(tags("natural"), "volcano")) return PoiClass::Peak;
    if (tags("amenity")) return PoiClass::Amenity;
    if (tags("shop")) return PoiClass::Shop;
    if (tags("tourism")) return PoiClass::Tourism;
    if (tags("leisure")) return PoiClass::Leisure;
    if (tags("historic")) return PoiClass::Historic;
    if (tags("office")) return PoiClass::Office;
    return std::nullopt;
}

}  // namespace navmap::map
