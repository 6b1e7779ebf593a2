// The test scenes of `mbd plugin check`: two moving bodies (and the ground) and one element of
// the type under test, its keys from the type's own description (mbd/sdk/plugin_keys.hpp) and
// the user's --params.
#pragma once

#include <mbd/sdk/plugin_keys.hpp>
#include <mbd/sdk/body_state.hpp>

#include <random>
#include <string>
#include <vector>

namespace mbd::cli {

// The element's keys, one "key: value" line each: the user's --params, then the description's
// examples for the required keys the user did not give, and, when the user gave none, for the
// optional keys marked `in_check` (so --params never meets an example it conflicts with).
std::vector<std::string> element_keys(const PluginDescription* description, Dimension d,
                                      const std::vector<std::string>& params);

// Two-body test scene in which the joint connects ground-body and body-body (both bodies
// moving); with_points: a `points` key (one point per body, body axes) for joints that take
// their points so. The geometry written here is a placeholder: with_random_joint_geometry draws it.
std::string joint_scene(Dimension d, const std::string& type, const std::vector<std::string>& keys, bool with_points);

// A force between the two moving bodies a and b (two_bodies) or on a alone, at random points.
std::string force_scene(Dimension d, const std::string& type, const std::vector<std::string>& keys, bool two_bodies,
                        std::mt19937& rng);

}  // namespace mbd::cli
