// Scenes of the beam_slider tests (tests/test_beam_slider.cpp, tests/test_beam_slider_motion.cpp).
#pragma once

#include "support/test_support.hpp"

#include <string>

namespace mbd::test {

constexpr double kSliderG = 9.81;
constexpr double kSliderPi = 3.14159265358979323846;

// A cable `name` between two points (rho A = density, area 1).
inline std::string cable(const std::string& name, const std::string& from, const std::string& to, int elements,
                         double modulus, double second_moment) {
    return "  - {name: " + name + ", type: ancf_cable, from: " + from + ", to: " + to +
           ", elements: " + std::to_string(elements) + ", modulus: " + test::g17(modulus) +
           ", area: 1.0, second_moment: " + test::g17(second_moment) + ", density: 1.0}\n";
}

}  // namespace mbd::test
