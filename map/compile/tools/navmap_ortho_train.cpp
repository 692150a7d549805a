// SPDX-License-Identifier: Apache-2.0
// navmap-ortho-train: trains the orthoimage network (seed 6.6.1) on samples from across the
// globe against NASA's Blue Marble, writes its weights file and measures it on regions left out
// of training against two baselines (docs/orthoimage.md "Training").
//   navmap-ortho-train --marble /usr/share/marble/data --out data/ortho/ortho-mlp.nnw --seed 1
//   navmap-ortho-train --marble /usr/share/marble/data --evaluate data/ortho/ortho-mlp.nnw
// Exit status: 0 ok, 1 bad input (one line naming the file and the problem), 2 usage.

#include "navmap/cli/cli.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <sstream>

#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/ortho/color_difference.h"
#include "navmap/map/ortho/ortho_network.h"
#include "ortho_training_set.h"

namespace {

using namespace navmap::map::ortho;  // NOLINT: a tool's main file

struct Score {
    double mlp = 0, by_class = 0, by_latitude = 0;
    std::size_t n = 0;
};

std::array<float, 3> quantized(const OrthoNetwork& net, const OrthoInput& in) {
    const auto c = net.color(in);  // as the shader writes it
    return {c[0] / 255.0f, c[1] / 255.0f, c[2] / 255.0f};
}

std::string table(const OrthoNetwork& net, const TrainingSet& set, double& overall_land) {
    const auto regions = heldOutRegions();
    std::vector<Score> land(regions.size() + 1), all(regions.size() + 1);
    for (const GlobePixel& g : set.held_out) {
        const auto r = static_cast<std::size_t>(g.region);
        const auto out = quantized(net, g.sample.input);
        const bool is_land = g.cover != std::uint8_t(GlobalCover::Ocean) && g.cover != std::uint8_t(GlobalCover::Lake);
        for (Score* s : {&all[r], &all.back()}) {
            s->mlp += deltaE76(out, g.sample.target);
            s->by_class += deltaE76(set.all.byClass(g.cover), g.sample.target);
            s->by_latitude += deltaE76(set.all.byLatitude(g.lat), g.sample.target);
            ++s->n;
        }
        if (!is_land) continue;
        for (Score* s : {&land[r], &land.back()}) {
            s->mlp += deltaE76(out, g.sample.target);
            s->by_class += deltaE76(set.land.byClass(g.cover), g.sample.target);
            s->by_latitude += deltaE76(set.land.byLatitude(g.lat), g.sample.target);
            ++s->n;
        }
    }
    std::ostringstream o;
    char line[256];
    o << "| held-out region | pixels | MLP | class mean | latitude only |\n| --- | --- | --- | --- | --- |\n";
    auto row = [&](const std::string& name, const Score& s) {
        const double n = double(std::max<std::size_t>(s.n, 1));
        std::snprintf(line, sizeof line, "| %s | %zu | %.2f | %.2f | %.2f |\n", name.c_str(), s.n, s.mlp / n,
                      s.by_class / n, s.by_latitude / n);
        o << line;
    };
    for (std::size_t r = 0; r < regions.size(); ++r) row(regions[r].name + ", land", land[r]);
    row("**all regions, land**", land.back());
    row("**all regions, land and water**", all.back());
    overall_land = land.back().mlp / double(std::max<std::size_t>(land.back().n, 1));
    return o.str();
}

}  // namespace

int main(int argc, char** argv) {
    CLI::App app{"navmap-ortho-train: train the synthetic orthoimage network against Blue Marble (seed 6.6.1)"};
    navmap::cli::setUp(app, "navmap-ortho-train");
    std::string marble = kDebianMarbleData.string(), out, evaluate, report;
    TrainingSetOptions set_options;
    TrainOptions train_options;
    app.add_option("--marble", marble, "marble-qt-data folder")->capture_default_str();
    app.add_option("--out", out, "weights file to write");
    app.add_option("--evaluate", evaluate, "measure this weights file on the held-out regions instead of training");
    app.add_option("--report", report, "also write the held-out table (markdown) to this file");
    app.add_option("--seed", train_options.seed, "random seed (sampling and initial weights)")->capture_default_str();
    app.add_option("--samples", set_options.samples, "training samples drawn by the probability map")
        ->check(navmap::cli::integerIn(100, 3000000))
        ->capture_default_str();
    app.add_option("--epochs", train_options.epochs, "most epochs")
        ->check(navmap::cli::integerIn(1, 100000))
        ->capture_default_str();
    app.add_option("--patience", train_options.patience,
                   "stop after this many epochs without a better validation error (0: never)")
        ->check(navmap::cli::integerIn(0, 100000))
        ->capture_default_str();
    app.add_option("--hidden", train_options.hidden, "hidden neurons (seed 6.6.1: as many as inputs)")
        ->check(navmap::cli::integerIn(1, 1024))
        ->capture_default_str();
    if (const auto exit_status = navmap::cli::parse(app, argc, argv)) return *exit_status;
    if (out.empty() == evaluate.empty()) {
        std::cerr
            << "navmap-ortho-train: give one of --out (train) and --evaluate\nRun with --help for more information.\n";
        return navmap::cli::kExitUsage;
    }
    set_options.seed = train_options.seed;
    auto log = [](const std::string& s) { std::cerr << "navmap-ortho-train: " << s << '\n'; };
    const auto t0 = std::chrono::steady_clock::now();
    auto seconds = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };
    try {
        // A weights file to evaluate is checked before the minutes of reading the rasters.
        OrthoNetwork net;
        if (!evaluate.empty()) net = loadNetwork(evaluate);
        log("reading " + marble);
        const GlobalInputs inputs = loadGlobalInputs(marble);
        const RgbGrid blue_marble = loadBlueMarble(marble);
        const TrainingSet set = buildTrainingSet(inputs, blue_marble, set_options, log);
        if (evaluate.empty()) {
            train_options.progress = [&](int epoch, double train_mse, double val_mse) {
                if (epoch % 25 == 0 || epoch == 1) {
                    char line[128];
                    std::snprintf(line, sizeof line, "epoch %d: training MSE %.5f, validation MSE %.5f (%.0f s)", epoch,
                                  train_mse, val_mse, seconds());
                    log(line);
                }
            };
            net = trainNetwork(set.train, set.validation, train_options);
        }
        double overall = 0;
        const std::string t = table(net, set, overall);
        if (!out.empty()) {
            net.info.held_out_delta_e = static_cast<float>(overall);
            saveNetwork(net, out);
            log("wrote " + out + " (best epoch " + std::to_string(net.info.epochs) + ", " + std::to_string(seconds()) +
                " s)");
        }
        std::cout << "Mean CIE76 delta E against Blue Marble on the held-out regions (lower is better):\n\n" << t;
        if (!report.empty()) {
            std::ofstream r(report);
            r << t;
            if (!r) throw OrthoInputError("write(" + report + "): failed");
        }
        return 0;
    } catch (const OrthoInputError& e) {
        std::cerr << "navmap-ortho-train: " << e.what() << '\n';
    } catch (const Pn2Error& e) {
        std::cerr << "navmap-ortho-train: " << e.what() << '\n';
    } catch (const OrthoNetworkError& e) {
        std::cerr << "navmap-ortho-train: " << e.what() << '\n';
    }
    return navmap::cli::kExitFailure;
}
