// SPDX-License-Identifier: Apache-2.0
#pragma once
// Turns "--from"/"--to" text into a geographic point: "lat,lon" in degrees, or a place name
// looked up in the store's place labels (coarse tiles hold the important places), with a small
// built-in table of the seven Andorran parish towns as fallback. Name matching ignores case,
// accents, hyphens/apostrophes and a leading article ("les Escaldes" = "Escaldes").

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "navmap/common/geo_coordinate.h"
#include "navmap/ipc/net/result.h"
#include "navmap/map/tile_store.h"

namespace navmap::sim {

struct NamedPlace {
    std::string name;  ///< UTF-8 as in OSM (or the built-in table)
    GeoCoordinate point;
    float importance = 0.0f;
    bool builtin = false;
};

class PlaceResolver {
public:
    /// Only the built-in table.
    PlaceResolver();
    /// Place labels of the store's tiles down to 8 km tiles (suburbs and larger), then the table.
    static PlaceResolver fromStore(const map::TileStore& store);

    /// "42.5075,1.5218" (spaces allowed) or a place name. Errors: "unknown place 'X' (known: ...)",
    /// "latitude 95 out of range".
    [[nodiscard]] ipc::Result<GeoCoordinate> resolve(std::string_view text) const;
    [[nodiscard]] const std::vector<NamedPlace>& places() const { return m_places; }

    /// Parses "lat,lon"; nullopt if the text is not two numbers; an error if out of range.
    static std::optional<ipc::Result<GeoCoordinate>> parseLatLon(std::string_view text);
    /// Lower-case ASCII key of a name: accents folded, punctuation to spaces, leading article
    /// (el, la, les, l', the) dropped, spaces collapsed.
    static std::string normalize(std::string_view name);

private:
    std::vector<NamedPlace> m_places;  // store places first (by importance), then the table
};

}  // namespace navmap::sim
