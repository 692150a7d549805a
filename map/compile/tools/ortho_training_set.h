// SPDX-License-Identifier: Apache-2.0
#pragma once
// navmap-ortho-train's data: Blue Marble pixels with their network inputs from the global
// rasters (seed 6.6.1 "In the training phase, we take samples generated from a probability map
// of the earth's surface"), held-out regions left out of training, and the two baselines the
// network is measured against.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/compile/ortho/ortho_training.h"

namespace navmap::map::ortho {

/// A region left out of training, with a buffer of `buffer_deg` around it left out too (so
/// that neighbouring, correlated pixels do not leak into the training set).
struct HeldOutRegion {
    std::string name;
    double south, west, north, east;
};
std::vector<HeldOutRegion> heldOutRegions();
inline constexpr double kHeldOutBufferDeg = 1.0;

struct GlobePixel {
    TrainingSample sample;
    double lat = 0, lon = 0;
    std::uint8_t cover = 0;  ///< majority GlobalCover
    int region = -1;         ///< index into heldOutRegions(), -1: training
};

struct TrainingSetOptions {
    std::size_t samples = 100000;  ///< drawn from the training pixels by the probability map
    double validation_share = 0.1;
    std::uint32_t seed = 1;
};

/// Mean colour per land-cover class, and per degree of latitude, over every training pixel
/// (the baselines).
struct Baselines {
    std::array<std::array<double, 3>, kGlobalCoverCount> class_mean{};
    std::array<std::array<double, 3>, 180> latitude_mean{};
    [[nodiscard]] std::array<float, 3> byClass(std::uint8_t cover) const;
    [[nodiscard]] std::array<float, 3> byLatitude(double lat) const;
};

struct TrainingSet {
    std::vector<TrainingSample> train, validation;
    std::vector<GlobePixel> held_out;  ///< every pixel of the held-out regions
    Baselines land;                    ///< fitted on the training land pixels
    Baselines all;                     ///< fitted on all training pixels
    std::size_t training_pixels = 0;   ///< pixels outside the held-out regions and their buffers
};

/// Builds the set on Blue Marble's pixel grid. `log` gets progress lines.
TrainingSet buildTrainingSet(const GlobalInputs& inputs, const RgbGrid& blue_marble, const TrainingSetOptions& options,
                             const std::function<void(const std::string&)>& log);

}  // namespace navmap::map::ortho
