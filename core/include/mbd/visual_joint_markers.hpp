// Which derived shape marks which joint (the viewer page's check that joint markers ride
// on their bodies, viewer/test/browser.mjs). Kept apart from mbd/visual.hpp, which every
// model user includes.
#pragma once

#include <mbd/visual.hpp>

#include <cstddef>
#include <vector>

namespace mbd {

struct JointMarkerShape {
    int joint = -1;   // index into Model::joints
    int body = -1;    // the body it is drawn on, kGround: VisualScene::ground
    size_t shape = 0; // index into that body's (or the ground's) shape list
};

// build_visual_scene, also telling where each joint's derived marker went.
VisualScene build_visual_scene(const Model& model, std::vector<JointMarkerShape>& markers);

}  // namespace mbd
