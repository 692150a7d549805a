// SPDX-License-Identifier: Apache-2.0
#pragma once
// The global inputs of the synthetic orthoimages, decoded (seed 6.4): climate rasters, elevation,
// city lights, the Natural Earth land cover and the climate classes derived from them.
// loadGlobalInputs (marble_inputs.h) reads them from Debian's marble-qt-data.

#include "navmap/map/ortho/climate.h"
#include "navmap/map/ortho/geo_grid.h"
#include "navmap/map/ortho/natural_earth.h"

namespace navmap::map::ortho {

struct GlobalInputs {
    GeoGrid temp_dec, temp_jul;      ///< C
    GeoGrid precip_dec, precip_jul;  ///< mm per month
    GeoGrid elevation;               ///< m, bathymetry below 0
    GeoGrid lights;                  ///< 0..1
    NaturalEarthCover cover;
    ClimateGrid climate;  ///< buildClimateGrid of the four climate grids and the cover
};

}  // namespace navmap::map::ortho
