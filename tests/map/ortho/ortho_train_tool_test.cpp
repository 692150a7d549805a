// SPDX-License-Identifier: Apache-2.0
// navmap-ortho-train and the weights it shipped (data/ortho/ortho-mlp.nnw), and navmap-compile-ortho
// (navmap-compile with --ortho-data): the command-line
// conventions, clear errors for a missing data folder and a damaged weights file, and the shipped
// network measured again on the held-out regions, where it must beat both baselines.

#include <gtest/gtest.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "navmap/map/compile/ortho/marble_inputs.h"
#include "navmap/map/ortho/ortho_network.h"
#include "test_paths.h"

extern char** environ;

namespace {

namespace fs = std::filesystem;
using namespace navmap::map::ortho;

struct ToolRun {
    int status = -1;
    std::string output;  ///< stdout and stderr
};

ToolRun run(const std::string& args, const char* tool = NAVMAP_ORTHO_TRAIN_PATH) {
    const fs::path log = fs::temp_directory_path() / ("navmap-ortho-tool-" + std::to_string(::getpid()) + ".log");
    const std::string cmd = std::string("exec ") + tool + " " + args + " > " + log.string() + " 2>&1";
    const char* argv[] = {"/bin/sh", "-c", cmd.c_str(), nullptr};
    ToolRun r;
    pid_t pid = -1;
    if (posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char**>(argv), environ) != 0) return r;
    int status = 0;
    if (::waitpid(pid, &status, 0) == pid && WIFEXITED(status)) r.status = WEXITSTATUS(status);
    std::ifstream in(log);
    r.output.assign(std::istreambuf_iterator<char>(in), {});
    fs::remove(log);
    return r;
}

fs::path shippedWeights() { return navmap::test::dataDir() / "ortho" / "ortho-mlp.nnw"; }

TEST(OrthoTrainTool, CommandLineConventions) {
    const ToolRun version = run("--version");
    EXPECT_EQ(version.status, 0);
    EXPECT_TRUE(version.output.starts_with("navmap-ortho-train ")) << version.output;
    const ToolRun neither = run("--seed 3");
    EXPECT_EQ(neither.status, 2);
    EXPECT_NE(neither.output.find("give one of --out (train) and --evaluate"), std::string::npos) << neither.output;
    const ToolRun range = run("--out x.nnw --samples 12");
    EXPECT_EQ(range.status, 2);
    EXPECT_NE(range.output.find("'12' is not an integer in [100, 3000000]"), std::string::npos) << range.output;
}

// navmap-compile-ortho is navmap-compile with --ortho-data; the installed navmap-compile has no
// such option (it must not pull OpenImageIO into the navmapd package). A missing data folder is
// named in the error.
TEST(OrthoCompileTool, OnlyTheOrthoCompilerReadsOrthoData) {
    const ToolRun plain = run("--help", NAVMAP_COMPILE_PATH);
    EXPECT_EQ(plain.status, 0);
    EXPECT_EQ(plain.output.find("--ortho-data"), std::string::npos) << plain.output;
    const ToolRun ortho = run("--help", NAVMAP_COMPILE_ORTHO_PATH);
    EXPECT_EQ(ortho.status, 0);
    EXPECT_NE(ortho.output.find("--ortho-data"), std::string::npos) << ortho.output;

    const fs::path dir = fs::temp_directory_path() / ("navmap-no-ortho-data-" + std::to_string(::getpid()));
    const ToolRun missing = run("--osm " + (navmap::test::dataDir() / "andorra-2021-04-14.osm.pbf").string() +
                                    " --ortho-data " + dir.string() + " --out " + (dir.string() + ".navmap"),
                                NAVMAP_COMPILE_ORTHO_PATH);
    EXPECT_EQ(missing.status, 1) << missing.output;
    EXPECT_NE(missing.output.find(dir.string() + "/maps/earth/"), std::string::npos) << missing.output;
    EXPECT_FALSE(fs::exists(dir.string() + ".navmap"));
}

TEST(OrthoTrainTool, MissingDataAndDamagedWeightsAreClearErrors) {
    const fs::path dir = fs::temp_directory_path() / ("navmap-no-marble-" + std::to_string(::getpid()));
    const ToolRun missing = run("--marble " + dir.string() + " --out " + (dir / "w.nnw").string());
    EXPECT_EQ(missing.status, 1);
    EXPECT_NE(missing.output.find(dir.string() +
                                  "/maps/earth/temp-dec/temp-dec.jpg: no such file (is marble-qt-data installed?)"),
              std::string::npos)
        << missing.output;

    // A truncated weights file is refused before any raster is read.
    const fs::path cut = fs::temp_directory_path() / ("navmap-cut-" + std::to_string(::getpid()) + ".nnw");
    fs::copy_file(shippedWeights(), cut, fs::copy_options::overwrite_existing);
    const auto size = fs::file_size(cut);
    fs::resize_file(cut, size - 10);
    const ToolRun damaged = run("--marble " + dir.string() + " --evaluate " + cut.string());
    EXPECT_EQ(damaged.status, 1);
    EXPECT_NE(damaged.output.find(cut.string() + ": truncated: " + std::to_string(size - 10) + " of " +
                                  std::to_string(size) + " bytes"),
              std::string::npos)
        << damaged.output;
    fs::remove(cut);
}

TEST(OrthoTrainTool, ShippedWeightsRecordHowTheyWereMade) {
    const OrthoNetwork net = loadNetwork(shippedWeights());
    EXPECT_EQ(net.inputs, kOrthoInputs);
    EXPECT_EQ(net.hidden, kOrthoInputs);  // seed 6.6.1: as many hidden neurons as inputs
    EXPECT_EQ(net.info.seed, 1u);         // docs/orthoimage.md "Training" gives the command line
    EXPECT_EQ(net.info.samples, 90000u);
    EXPECT_GT(net.info.held_out_delta_e, 0.0f);
}

/// The "all regions, land" row of the held-out table: MLP, class mean, latitude only.
std::array<double, 3> landRow(const std::string& table) {
    const std::string key = "| **all regions, land** |";
    const auto at = table.find(key);
    if (at == std::string::npos) return {-1, -1, -1};
    std::istringstream row(table.substr(at + key.size()));
    std::size_t pixels = 0;
    char bar = 0;
    std::array<double, 3> v{};
    row >> pixels >> bar >> v[0] >> bar >> v[1] >> bar >> v[2];
    return v;
}

TEST(OrthoTrainTool, ShippedWeightsBeatBothBaselinesOnTheHeldOutRegions) {
    if (!fs::exists(kDebianMarbleData / "maps/earth/bluemarble/bluemarble.jpg")) {
        GTEST_SKIP() << kDebianMarbleData << " is absent (Debian package marble-qt-data, scripts/install-deps.sh)";
    }
    const ToolRun r = run("--evaluate " + shippedWeights().string());
    ASSERT_EQ(r.status, 0) << r.output;
    const auto v = landRow(r.output);
    ASSERT_GT(v[0], 0.0) << r.output;
    EXPECT_LT(v[0], v[1]) << "MLP against the class means\n" << r.output;
    EXPECT_LT(v[0], v[2]) << "MLP against the latitude-only model\n" << r.output;
    // The figure recorded in the file at training time is the one measured now.
    EXPECT_NEAR(v[0], loadNetwork(shippedWeights()).info.held_out_delta_e, 0.01);
}

}  // namespace
