// Modes of a linearised system (issue 17): eigenvalues of A, natural frequencies, damping
// ratios and mode shapes in the independent and joint coordinates; coordinates on which
// the dynamics do not depend (ignorable: position on the ground, heading) are set apart
// with their zero eigenvalues instead of being mixed with the rest.
#pragma once

#include <mbd/linearisation.hpp>

#include <Eigen/Core>

#include <complex>
#include <string>
#include <vector>

namespace mbd {

struct Mode {
    std::complex<double> eigenvalue;      // of a complex pair, the one with Im > 0
    bool oscillatory = false;             // a complex pair
    double natural_frequency = 0.0;       // |lambda|, rad/s
    double damped_frequency = 0.0;        // |Im lambda|, rad/s
    double damping_ratio = 0.0;           // -Re lambda / |lambda| (0 for lambda = 0)
    Eigen::VectorXcd shape;               // position part, independent coordinates, max |.| = 1
    Eigen::VectorXcd joint_shape;         // the same in joint coordinates
};

struct ModeAnalysis {
    std::vector<Mode> modes;              // ascending natural frequency
    std::vector<int> ignorable;           // independent coordinates (indices) A does not depend on
};

// Columns of A's position block below tolerance * max|A| count as ignorable.
ModeAnalysis modes_of(const LinearModel& linear, double ignorable_tolerance = 1e-8);

}  // namespace mbd
