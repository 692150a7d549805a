// SPDX-License-Identifier: Apache-2.0
// PlaceResolver: "lat,lon" parsing, name normalization, the built-in table.
#include <gtest/gtest.h>

#include "navmap/sim/place_resolver.h"

namespace navmap::sim {
namespace {

TEST(PlaceResolver, ParsesLatLon) {
    auto p = PlaceResolver::parseLatLon("42.5075,1.5218");
    ASSERT_TRUE(p && p->ok());
    EXPECT_DOUBLE_EQ(p->value().lat_deg, 42.5075);
    EXPECT_DOUBLE_EQ(p->value().lon_deg, 1.5218);
    p = PlaceResolver::parseLatLon(" -33.9 , +151.2 ");
    ASSERT_TRUE(p && p->ok());
    EXPECT_DOUBLE_EQ(p->value().lat_deg, -33.9);
    EXPECT_DOUBLE_EQ(p->value().lon_deg, 151.2);
    for (const char* text : {"Encamp", "42.5", "42.5,", ",1.5", "1,2,3", "a,b", "42.5,1.5x", "nan,1", "inf,1", ""}) {
        EXPECT_FALSE(PlaceResolver::parseLatLon(text).has_value()) << text;
    }
    p = PlaceResolver::parseLatLon("95,1");
    ASSERT_TRUE(p.has_value());
    ASSERT_FALSE(p->ok());
    EXPECT_EQ(p->error().message, "latitude 95.000000 is outside [-90, 90]");
    p = PlaceResolver::parseLatLon("42,-181");
    ASSERT_TRUE(p.has_value() && !p->ok());
    EXPECT_EQ(p->error().message, "longitude -181.000000 is outside [-180, 180]");
}

TEST(PlaceResolver, NormalizesNames) {
    EXPECT_EQ(PlaceResolver::normalize("Sant Julià de Lòria"), "sant julia de loria");
    EXPECT_EQ(PlaceResolver::normalize("les Escaldes"), "escaldes");
    EXPECT_EQ(PlaceResolver::normalize("Escaldes-Engordany"), "escaldes engordany");
    EXPECT_EQ(PlaceResolver::normalize("  La   Massana "), "massana");
    EXPECT_EQ(PlaceResolver::normalize("l'Aldosa"), "aldosa");
    EXPECT_EQ(PlaceResolver::normalize("ANDORRA LA VELLA"), "andorra la vella");
    EXPECT_EQ(PlaceResolver::normalize("La"), "la");  // an article alone stays
    EXPECT_EQ(PlaceResolver::normalize("Ça·Ñ"), "ca n");
    EXPECT_EQ(PlaceResolver::normalize(std::string("\xC3", 1)), "");  // truncated UTF-8
}

TEST(PlaceResolver, BuiltInTableKnowsTheParishTowns) {
    const PlaceResolver r;
    for (const char* name : {"Andorra la Vella", "les Escaldes", "Escaldes", "Encamp", "Sant Julia de Loria",
                             "sant julià de lòria", "La Massana", "Massana", "Ordino", "canillo"}) {
        auto p = r.resolve(name);
        ASSERT_TRUE(p.ok()) << name;
        EXPECT_NEAR(p.value().lat_deg, 42.5, 0.1) << name;
        EXPECT_NEAR(p.value().lon_deg, 1.55, 0.06) << name;
    }
    auto coords = r.resolve("42.1,1.2");
    ASSERT_TRUE(coords.ok());
    EXPECT_DOUBLE_EQ(coords.value().lat_deg, 42.1);
    auto unknown = r.resolve("Atlantis");
    ASSERT_FALSE(unknown.ok());
    EXPECT_EQ(unknown.error().message.rfind(
                  "unknown place 'Atlantis' (give \"lat,lon\" or a place name such as Andorra la Vella", 0),
              0U)
        << unknown.error().message;
    EXPECT_FALSE(r.resolve("  ").ok());
}

}  // namespace
}  // namespace navmap::sim
