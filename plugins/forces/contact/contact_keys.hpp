// The keys every compliant contact type shares (the normal law and friction of
// mbd/sdk/contact.hpp), for the types' key descriptions (mbd/sdk/plugin_keys.hpp).
#pragma once

#include <mbd/sdk/plugin_keys.hpp>

// A brace list of mbd::PluginKey, to end a type's own list.
#define MBD_CONTACT_LAW_KEYS \
    {"stiffness", "k of F_n = k d^n + c d^n d_dot (N/m^n), > 0", nullptr, "100"}, \
    {"exponent", "n, > 0 (1.5: Hertz contact of spheres; 1: linear)", "1.5", "1"}, \
    {"damping", "c (N s/m^(n+1)), >= 0; or restitution", "0", "2", nullptr, true}, \
    {"restitution", "e in (0, 1], with impact_velocity: the damping fitted to it; or damping", "none", "0.8"}, \
    {"impact_velocity", "the approach speed (m/s, > 0) the restitution is fitted to", "none: required with restitution", "2.4"}, \
    {"restitution_model", "lankarani_nikravesh or hunt_crossley", "lankarani_nikravesh", "hunt_crossley"}, \
    {"static_friction", "mu_s, >= 0 (0: frictionless)", "0", "0.3", nullptr, true}, \
    {"kinetic_friction", "mu_k, 0 <= mu_k <= mu_s", "static_friction", "0.2"}, \
    {"stiction_velocity", "v_s (m/s, > 0): the slip speed within which mu rises to mu_s", "1e-6", "0.5", nullptr, true},
