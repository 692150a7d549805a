// SPDX-License-Identifier: Apache-2.0
#include "navmap/map/compile/ortho/ortho_training.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "navmap/map/ortho/rng.h"

namespace navmap::map::ortho {

namespace {

// iRPROP- parameters (FANN's defaults, seed 6.6.1).
constexpr float kIncrease = 1.2f, kDecrease = 0.5f, kDeltaMin = 1e-6f, kDeltaMax = 50.0f, kDeltaZero = 0.1f;

struct Rprop {
    std::vector<float> delta, previous;
    explicit Rprop(std::size_t n) : delta(n, kDeltaZero), previous(n, 0.0f) {}
    void step(float* weights, const float* gradient, std::size_t n, std::size_t offset) {
        for (std::size_t i = 0; i < n; ++i) {
            const std::size_t k = offset + i;
            const float g = gradient[i];
            const float s = g * previous[k];
            if (s > 0.0f) {
                delta[k] = std::min(delta[k] * kIncrease, kDeltaMax);
            } else if (s < 0.0f) {
                delta[k] = std::max(delta[k] * kDecrease, kDeltaMin);
                previous[k] = 0.0f;  // iRPROP-: no step after a sign change
                continue;
            }
            if (g > 0.0f) weights[i] -= delta[k];
            if (g < 0.0f) weights[i] += delta[k];
            previous[k] = g;
        }
    }
};

}  // namespace

double meanSquaredError(const OrthoNetwork& net, const std::vector<TrainingSample>& samples) {
    if (samples.empty()) return 0.0;
    double sum = 0.0;
    for (const auto& s : samples) {
        const auto y = net.forward(s.input);
        for (std::size_t c = 0; c < 3; ++c) sum += double(y[c] - s.target[c]) * (y[c] - s.target[c]);
    }
    return sum / (3.0 * static_cast<double>(samples.size()));
}

OrthoNetwork trainNetwork(const std::vector<TrainingSample>& train, const std::vector<TrainingSample>& validation,
                          const TrainOptions& options) {
    const int n = kOrthoInputs, h = options.hidden;
    OrthoNetwork net = OrthoNetwork::zeros(n, h);
    net.info.seed = options.seed;
    net.info.samples = static_cast<std::uint32_t>(train.size());
    Rng rng(options.seed);
    for (auto& w : net.w0) w = static_cast<float>(rng.uniform(-1.0, 1.0));
    for (auto& w : net.b0) w = static_cast<float>(rng.uniform(-1.0, 1.0));
    const double out_scale = 1.0 / std::sqrt(static_cast<double>(h));
    for (auto& w : net.w1) w = static_cast<float>(rng.uniform(-out_scale, out_scale));
    std::array<double, 3> mean{};
    for (const auto& s : train) {
        for (std::size_t c = 0; c < 3; ++c) mean[c] += s.target[c];
    }
    for (std::size_t c = 0; c < 3; ++c)
        net.b1[c] = train.empty() ? 0.0f : static_cast<float>(mean[c] / double(train.size()));

    const std::size_t n0 = net.w0.size(), nb0 = net.b0.size(), n1 = net.w1.size();
    Rprop rprop(n0 + nb0 + n1 + 3);
    std::vector<double> g0(n0), gb0(nb0), g1(n1);
    std::array<double, 3> gb1{};
    std::vector<float> f0(n0), fb0(nb0), f1(n1);
    std::array<float, 3> fb1{};
    std::vector<float> a(static_cast<std::size_t>(h)), da(static_cast<std::size_t>(h));
    OrthoNetwork best = net;
    double best_error = std::numeric_limits<double>::infinity();
    int since_best = 0;
    for (int epoch = 1; epoch <= options.epochs; ++epoch) {
        std::fill(g0.begin(), g0.end(), 0.0);
        std::fill(gb0.begin(), gb0.end(), 0.0);
        std::fill(g1.begin(), g1.end(), 0.0);
        gb1 = {};
        double sse = 0.0;
        for (const auto& s : train) {
            const auto y = net.forward(s.input, a);  // a: sigmoid activations
            std::array<float, 3> dy{};
            for (std::size_t c = 0; c < 3; ++c) {
                dy[c] = y[c] - s.target[c];
                sse += double(dy[c]) * dy[c];
                gb1[c] += dy[c];
            }
            for (int j = 0; j < h; ++j) {
                const auto uj = static_cast<std::size_t>(j);
                const float* w1 = &net.w1[uj * 3];
                g1[uj * 3] += a[uj] * dy[0];
                g1[uj * 3 + 1] += a[uj] * dy[1];
                g1[uj * 3 + 2] += a[uj] * dy[2];
                const float ds = w1[0] * dy[0] + w1[1] * dy[1] + w1[2] * dy[2];
                da[uj] = ds * a[uj] * (1.0f - a[uj]);
                gb0[uj] += da[uj];
            }
            for (int k = 0; k < kOrthoActive; ++k) {
                const float v = s.input.value(k);
                if (v == 0.0f || s.input.node(k) >= n) continue;
                double* row = &g0[static_cast<std::size_t>(s.input.node(k)) * static_cast<std::size_t>(h)];
                for (int j = 0; j < h; ++j) row[j] += v * da[static_cast<std::size_t>(j)];
            }
        }
        const double train_mse = train.empty() ? 0.0 : sse / (3.0 * static_cast<double>(train.size()));
        std::transform(g0.begin(), g0.end(), f0.begin(), [](double v) { return static_cast<float>(v); });
        std::transform(gb0.begin(), gb0.end(), fb0.begin(), [](double v) { return static_cast<float>(v); });
        std::transform(g1.begin(), g1.end(), f1.begin(), [](double v) { return static_cast<float>(v); });
        for (std::size_t c = 0; c < 3; ++c) fb1[c] = static_cast<float>(gb1[c]);
        rprop.step(net.w0.data(), f0.data(), n0, 0);
        rprop.step(net.b0.data(), fb0.data(), nb0, n0);
        rprop.step(net.w1.data(), f1.data(), n1, n0 + nb0);
        rprop.step(net.b1.data(), fb1.data(), 3, n0 + nb0 + n1);
        const double val_mse = validation.empty() ? train_mse : meanSquaredError(net, validation);
        if (options.progress) options.progress(epoch, train_mse, val_mse);
        net.info.epochs = static_cast<std::uint32_t>(epoch);
        if (val_mse < best_error) {
            best_error = val_mse;
            best = net;
            since_best = 0;
        } else if (options.patience > 0 && ++since_best >= options.patience) {
            break;
        }
    }
    return validation.empty() ? net : best;
}

}  // namespace navmap::map::ortho
