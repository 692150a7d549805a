// SPDX-License-Identifier: Apache-2.0
#pragma once
// Training of the orthoimage network (seed 6.6.1): full-batch improved resilient
// backpropagation (iRPROP-, Igel and Huesken, the algorithm of the FANN library the seed used) on
// the mean squared error of R, G, B, keeping the weights of the epoch with the lowest error on a
// validation set. Deterministic for a given seed. Single-threaded.

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "navmap/map/ortho/ortho_network.h"

namespace navmap::map::ortho {

struct TrainingSample {
    OrthoInput input;
    std::array<float, 3> target{};  ///< sRGB in [0, 1]
};

struct TrainOptions {
    int hidden = kOrthoInputs;  ///< seed 6.6.1: as many hidden neurons as inputs
    int epochs = 300;
    std::uint32_t seed = 1;
    /// Stop when the validation error has not improved for this many epochs (0: never).
    int patience = 60;
    /// Called after every epoch with the mean squared errors (training, validation).
    std::function<void(int epoch, double train_mse, double validation_mse)> progress;
};

/// Trains from a seeded random start; `validation` may be empty (then the last epoch is kept).
OrthoNetwork trainNetwork(const std::vector<TrainingSample>& train, const std::vector<TrainingSample>& validation,
                          const TrainOptions& options);
/// Mean squared error per channel over the samples.
double meanSquaredError(const OrthoNetwork& net, const std::vector<TrainingSample>& samples);

}  // namespace navmap::map::ortho
