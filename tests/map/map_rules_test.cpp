// SPDX-License-Identifier: Apache-2.0
// Tag interpretation: highway -> FRC, building heights, speeds, one-way rules, area/place classes.
#include <gtest/gtest.h>

#include <map>
#include <string>

#include "navmap/map/compile/tag_rules.h"
#include "navmap/map/road_class.h"

using namespace navmap::map;

namespace {

TagLookup tags(const std::map<std::string, std::string>& kv) {
    return [kv](const char* key) -> const char* {
        const auto it = kv.find(key);
        return it == kv.end() ? nullptr : it->second.c_str();
    };
}

}  // namespace

TEST(RoadClass, MapsHighwayValuesInImportanceOrder) {
    const char* order[] = {"motorway",    "trunk",   "primary",    "secondary", "tertiary", "unclassified",
                           "residential", "service", "pedestrian", "track",     "path"};
    for (int i = 0; i < kRoadClassCount; ++i) {
        const auto m = roadClassFromHighway(order[i]);
        ASSERT_TRUE(m) << order[i];
        EXPECT_EQ(static_cast<int>(m->cls), i) << order[i];
        EXPECT_FALSE(m->link);
        EXPECT_EQ(roadClassName(m->cls), order[i]);
    }
}

TEST(RoadClass, LinksFootwaysAndNonRoads) {
    EXPECT_EQ(roadClassFromHighway("motorway_link")->cls, RoadClass::Motorway);
    EXPECT_TRUE(roadClassFromHighway("trunk_link")->link);
    EXPECT_EQ(roadClassFromHighway("living_street")->cls, RoadClass::Residential);
    EXPECT_EQ(roadClassFromHighway("footway")->cls, RoadClass::Path);
    EXPECT_EQ(roadClassFromHighway("steps")->cls, RoadClass::Path);
    EXPECT_EQ(roadClassFromHighway("cycleway")->cls, RoadClass::Path);
    EXPECT_FALSE(roadClassFromHighway("construction"));
    EXPECT_FALSE(roadClassFromHighway("bus_stop"));
    EXPECT_FALSE(roadClassFromHighway(""));
    EXPECT_GT(defaultSpeedKmh(RoadClass::Motorway), defaultSpeedKmh(RoadClass::Residential));
}

TEST(BuildingHeight, HeightThenLevelsThenDefault) {
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"height", "12"}})), 12.0f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"height", "12.5 m"}, {"building:levels", "9"}})), 12.5f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"height", "7,5"}})), 7.5f);
    EXPECT_NEAR(buildingHeight(tags({{"height", "40 ft"}})), 12.192f, 1e-4);
    EXPECT_NEAR(buildingHeight(tags({{"height", "10'6\""}})), 3.2004f, 1e-4);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"building:levels", "4"}})), 12.0f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"building:levels", "4"}, {"roof:levels", "2"}})), 15.0f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"height", "tall"}, {"building:levels", "2"}})), 6.0f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"building", "yes"}})), 8.0f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"building", "yes"}}), 5.0f), 5.0f);
    EXPECT_FLOAT_EQ(buildingHeight(tags({{"building:levels", "-3"}})), 8.0f);
    EXPECT_FLOAT_EQ(buildingMinHeight(tags({{"building:min_level", "2"}})), 6.0f);
    EXPECT_FLOAT_EQ(buildingMinHeight(tags({{"min_height", "4 m"}})), 4.0f);
    EXPECT_FLOAT_EQ(buildingMinHeight(tags({})), 0.0f);
}

TEST(TagRules, MaxspeedAndOneway) {
    EXPECT_FLOAT_EQ(*parseMaxspeedKmh("50"), 50.0f);
    EXPECT_NEAR(*parseMaxspeedKmh("30 mph"), 48.28f, 0.01);
    EXPECT_FLOAT_EQ(*parseMaxspeedKmh("90 km/h"), 90.0f);
    EXPECT_FALSE(parseMaxspeedKmh("none"));
    EXPECT_FALSE(parseMaxspeedKmh("ES:urban"));
    EXPECT_EQ(onewayDirection(tags({{"oneway", "yes"}})), 1);
    EXPECT_EQ(onewayDirection(tags({{"oneway", "-1"}})), -1);
    EXPECT_EQ(onewayDirection(tags({{"highway", "motorway"}})), 1);
    EXPECT_EQ(onewayDirection(tags({{"highway", "motorway"}, {"oneway", "no"}})), 0);
    EXPECT_EQ(onewayDirection(tags({{"highway", "primary"}, {"junction", "roundabout"}})), 1);
    EXPECT_EQ(onewayDirection(tags({{"highway", "primary"}})), 0);
}

TEST(TagRules, AreaPlaceAndPoiClasses) {
    EXPECT_EQ(areaClassFromTags(tags({{"natural", "water"}})), AreaClass::Water);
    EXPECT_EQ(areaClassFromTags(tags({{"landuse", "forest"}})), AreaClass::Forest);
    EXPECT_EQ(areaClassFromTags(tags({{"natural", "wood"}})), AreaClass::Forest);
    EXPECT_EQ(areaClassFromTags(tags({{"landuse", "residential"}})), AreaClass::Residential);
    EXPECT_EQ(areaClassFromTags(tags({{"leisure", "park"}})), AreaClass::Park);
    EXPECT_EQ(areaClassFromTags(tags({{"waterway", "riverbank"}})), AreaClass::Water);
    // The schema draws no area for a value it does not classify, nor for boundaries and places.
    EXPECT_FALSE(areaClassFromTags(tags({{"landuse", "something_new"}})));
    EXPECT_FALSE(areaClassFromTags(tags({{"type", "boundary"}, {"natural", "mountain_range"}})));
    EXPECT_FALSE(areaClassFromTags(tags({{"type", "boundary"}, {"natural", "wood"}})));
    EXPECT_FALSE(areaClassFromTags(tags({{"natural", "bay"}})));
    EXPECT_EQ(areaClassFromTags(tags({{"leisure", "marina"}, {"seamark:type", "harbour"}})), AreaClass::Harbour);
    EXPECT_EQ(areaClassFromTags(tags({{"man_made", "breakwater"}})), AreaClass::Pier);
    EXPECT_EQ(areaLabelClassFromTags(tags({{"natural", "strait"}})), PlaceClass::Locality);
    EXPECT_EQ(areaLabelClassFromTags(tags({{"place", "region"}})), PlaceClass::State);
    EXPECT_FALSE(areaLabelClassFromTags(tags({{"natural", "wood"}})));
    EXPECT_FALSE(areaClassFromTags(tags({{"highway", "primary"}})));
    EXPECT_EQ(placeClassFromTag("town"), PlaceClass::Town);
    EXPECT_EQ(placeClassFromTag("hamlet"), PlaceClass::Hamlet);
    EXPECT_EQ(placeClassFromTag("locality"), PlaceClass::Locality);
    EXPECT_GT(placeImportance(PlaceClass::Town), placeImportance(PlaceClass::Village));
    EXPECT_GT(placeImportance(PlaceClass::Village), placeImportance(PlaceClass::Hamlet));
    EXPECT_EQ(poiClassFromTags(tags({{"amenity", "restaurant"}})), PoiClass::Amenity);
    EXPECT_EQ(poiClassFromTags(tags({{"natural", "peak"}})), PoiClass::Peak);
    EXPECT_FALSE(poiClassFromTags(tags({{"name", "x"}})));
}
