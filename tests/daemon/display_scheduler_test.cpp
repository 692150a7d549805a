// SPDX-License-Identifier: Apache-2.0
// DisplayScheduler with the no-op renderer on the Andorra store: every display renders the
// vehicle on the same ground, whatever the order the profiles are listed in (the pose's height
// comes from one terrain query, not from the first display's view).

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <memory>
#include <thread>

#include "display_scheduler.h"
#include "navmap/daemon/vehicle/vehicle_state_estimator.h"
#include "navmap/map/map_scene.h"
#include "server_options.h"
#include "test_paths.h"

using namespace navmap;
using namespace navmap::daemon;
using namespace std::chrono_literals;

namespace {

std::filesystem::path storePath() { return test::binaryDir() / "andorra.navmap"; }

// A vehicle standing in Andorra la Vella, heading north-east, with a fresh fix.
std::shared_ptr<const VehicleState> standingVehicle(const map::Projection& projection) {
    VehicleStateEstimator estimator(projection, nullptr);
    const ipc::CanTime t = ipc::CanClock::now();
    ipc::VehicleSample fix;
    fix.set(ipc::VssSignal::Latitude, 42.50770, t);
    fix.set(ipc::VssSignal::Longitude, 1.52190, t);
    fix.set(ipc::VssSignal::Heading, 45.0, t);
    fix.set(ipc::VssSignal::FixType, 5, t);
    estimator.addSample(fix);
    ipc::VehicleSample motion;
    motion.set(ipc::VssSignal::Speed, 0.0, t);
    motion.set(ipc::VssSignal::YawRate, 0.0, t);
    estimator.addSample(motion);
    return estimator.snapshot();
}

struct Heights {
    std::map<std::string, double> by_display;  // the z each display rendered the vehicle at
    double ground = 0.0;                       // the pose source's terrain query there
};

// The profiles of a start, with the no-op renderer, around the standing vehicle, every display
// rendered whether watched or not.
struct StandingStart {
    explicit StandingStart(const std::vector<DisplayProfile>& profiles)
        : scene(map::MapScene::open(storePath())),
          vehicle(standingVehicle(scene.projection())),
          poses([v = vehicle](ipc::CanTime t) { return v->poseAt(t); }, scene.cache, scene.toPlanar(42.5, 1.5)),
          dir(std::filesystem::temp_directory_path() / ("navmap-scheduler-" + std::to_string(::getpid()))),
          config(configFor(profiles, dir)),
          frames(frameServerOptions(config)) {
        EXPECT_TRUE(frames.start());
        scheduler = std::make_unique<DisplayScheduler>(
            config, DisplayScheduler::Options{.noop_renderer = true, .render_all = true, .ortho_weights = {}},
            scene.cache, scene.projection(), frames, std::chrono::steady_clock::now(), Log(Log::kErr));
        context.style = render::MapStyle::day();
    }
    ~StandingStart() {
        scheduler.reset();
        frames.stop();
        std::filesystem::remove_all(dir);
    }
    static DaemonConfig configFor(const std::vector<DisplayProfile>& profiles, const std::filesystem::path& dir) {
        std::filesystem::create_directories(dir);
        DaemonConfig c;
        c.profiles = profiles;
        c.frame_socket = dir / "frames.sock";
        return c;
    }

    map::MapScene scene;
    std::shared_ptr<const VehicleState> vehicle;
    PoseSource poses;
    std::filesystem::path dir;
    DaemonConfig config;
    ipc::FrameServer frames;
    std::unique_ptr<DisplayScheduler> scheduler;
    FrameContext context;
};

// Renders the profiles in the given order until every display has the tiles its camera wants.
Heights renderInOrder(const std::vector<DisplayProfile>& profiles) {
    StandingStart start(profiles);
    map::MapScene& scene = start.scene;
    const PoseSource& poses = start.poses;
    DisplayScheduler& scheduler = *start.scheduler;
    const FrameContext& context = start.context;
    bool settled = false;
    for (int i = 0; i < 100 && !settled; ++i) {
        (void)scheduler.tick(std::chrono::steady_clock::now() + std::chrono::seconds(i), poses, context);
        settled = std::all_of(scheduler.displays().begin(), scheduler.displays().end(),
                              [](const auto& d) { return d->stats().rendered > 1 && d->stats().tiles_wanted == 0; });
        (void)scene.cache->waitIdle(200ms);
    }
    EXPECT_TRUE(settled) << "the displays' tiles did not load";
    (void)scheduler.tick(std::chrono::steady_clock::now() + 200s, poses, context);  // one more frame, all resident
    Heights h;
    for (const auto& d : scheduler.displays()) h.by_display[d->profile().name] = d->lastPose().position.z;
    const auto& p = scheduler.displays().front()->lastPose().position;
    h.ground = poses.ground()(p.x, p.y);
    return h;
}

}  // namespace

TEST(DisplayScheduler, ThePoseHeightDoesNotDependOnTheOrderOfTheDisplays) {
    if (!std::filesystem::exists(storePath())) {
        GTEST_SKIP() << "no compiled store at " << storePath() << " (build the navmap_default_store target)";
    }
    std::vector<DisplayProfile> profiles = defaultProfiles();  // cluster, hud, center
    ASSERT_EQ(profiles.size(), 3u);
    const Heights forward = renderInOrder(profiles);
    std::reverse(profiles.begin(), profiles.end());
    const Heights reversed = renderInOrder(profiles);

    EXPECT_GT(forward.ground, 900.0) << "Andorra la Vella lies above 1000 m: the terrain was resident";
    EXPECT_EQ(forward.ground, reversed.ground);
    ASSERT_EQ(forward.by_display.size(), 3u);
    for (const auto& [name, z] : forward.by_display) {
        EXPECT_EQ(z, forward.ground) << name << " (cluster listed first)";
        EXPECT_EQ(reversed.by_display.at(name), forward.ground) << name << " (center listed first)";
    }
}

// Start-up, cluster first: no display renders its first frame before every display listed
// before it has rendered its own (the first frame uploads every tile and compiles the driver's
// shader code: the CPU the cluster needs). Checked after every tick of a start, with the HUD's
// fewer tiles resident before the cluster's; in both listing orders.
TEST(DisplayScheduler, NoDisplayStartsBeforeTheDisplaysListedBeforeIt) {
    if (!std::filesystem::exists(storePath())) {
        GTEST_SKIP() << "no compiled store at " << storePath() << " (build the navmap_default_store target)";
    }
    std::vector<DisplayProfile> profiles = defaultProfiles();  // cluster, hud, center
    for (int order = 0; order < 2; ++order) {
        if (order == 1) std::reverse(profiles.begin(), profiles.end());
        StandingStart start(profiles);
        DisplayScheduler& scheduler = *start.scheduler;
        const auto& displays = scheduler.displays();
        std::vector<int> first_tick(displays.size(), -1);
        for (int tick = 0; tick < 200 && std::count(first_tick.begin(), first_tick.end(), -1) > 0; ++tick) {
            (void)scheduler.tick(std::chrono::steady_clock::now() + std::chrono::seconds(tick), start.poses,
                                 start.context);
            for (std::size_t i = 0; i < displays.size(); ++i)
                if (first_tick[i] < 0 && displays[i]->started()) first_tick[i] = tick;
            for (std::size_t i = 1; i < displays.size(); ++i)
                if (displays[i]->started()) {
                    EXPECT_TRUE(displays[i - 1]->started()) << displays[i]->profile().name << " started at tick "
                                                            << tick << " before " << displays[i - 1]->profile().name;
                }
            std::this_thread::sleep_for(5ms);  // the loader's pace, not the test's
        }
        for (std::size_t i = 0; i < displays.size(); ++i) {
            EXPECT_GE(first_tick[i], 0) << displays[i]->profile().name << " never rendered";
            std::printf("order %d: %s first rendered at tick %d, %llu frames held back\n", order,
                        displays[i]->profile().name.c_str(), first_tick[i],
                        static_cast<unsigned long long>(displays[i]->stats().held_back));
        }
    }
}
