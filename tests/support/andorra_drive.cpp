// SPDX-License-Identifier: Apache-2.0
#include "andorra_drive.h"

#include <gtest/gtest.h>

#include "test_paths.h"

namespace navmap::test {

DriveScene& andorraDrive() {
    static DriveScene d = DriveScene::open(binaryDir() / "andorra.navmap", kAndorraLaVella, kEncamp);
    return d;
}

render::MapFrame settledAndorraFrame(render::ViewMode mode, int width, int height, double measure_m, double speed_mps) {
    DriveScene& d = andorraDrive();
    render::CameraRig rig;
    rig.setMode(mode);
    const double aspect = double(width) / height;
    const auto shot = d.settle(rig, measure_m, speed_mps, aspect, height);
    EXPECT_TRUE(shot.complete) << "tiles of the view at " << measure_m << " m did not load in time";
    return d.frameFor(shot, aspect, height);
}

}  // namespace navmap::test
