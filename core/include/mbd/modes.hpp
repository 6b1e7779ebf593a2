// Modes of a linearised system (issue 17): eigenvalues of A, natural frequencies, damping
// ratios and mode shapes in the independent and joint coordinates; coordinates on which
// the dynamics do not depend (ignorable: position on the ground, heading, a wheel's spin
// angle) are set apart with their zero eigenvalues instead of being mixed with the rest.
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
    bool free_velocity = false;           // lambda = 0 of a velocity the rest does not see (modes_of)
    double natural_frequency = 0.0;       // |lambda|, rad/s
    double damped_frequency = 0.0;        // |Im lambda|, rad/s
    double damping_ratio = 0.0;           // -Re lambda / |lambda| (0 for lambda = 0)
    Eigen::VectorXcd shape;               // position part, independent coordinates, max |.| = 1
    Eigen::VectorXcd joint_shape;         // the same in joint coordinates
};

// A direction of the independent positions that the rest of the motion does not see: the
// span of these is the largest set S of position directions with A S within S and A
// nilpotent on S (a position the dynamics do not depend on, A s = 0, such as the position
// on the ground or a wheel's spin angle; or one that only drives another such, like the
// heading of a bicycle, whose rate moves its lateral position). Each has eigenvalue zero.
struct IgnorableDirection {
    Eigen::VectorXd shape;                // in the independent coordinates, its pivot entry 1
    Eigen::VectorXd joint_shape;          // the same in joint coordinates
    int coordinate = 0;                   // its pivot: the independent coordinate it is named by
    bool single = true;                   // only that coordinate (else a combination)
};

struct ModeAnalysis {
    std::vector<Mode> modes;              // ascending natural frequency
    std::vector<IgnorableDirection> ignorable;
};

// Singular values below tolerance * max|A| count as zero in finding the ignorable directions.
// The eigenvalues of the rest are polished by Newton's method as roots of det(lambda I - A) /
// lambda^s (s zero eigenvalues set apart), whose coefficients carry A's error only, not the
// eps^(1/s) spread that differences give a nilpotent block (an eigenvalue near zero: a
// bicycle's capsize mode near its critical speed, tests/test_bicycle.cpp).
ModeAnalysis modes_of(const LinearModel& linear, double ignorable_tolerance = 1e-8);

// "frame.x" for a single coordinate, "frame.rz + 0.35 fork.rz" for a combination.
std::string describe(const IgnorableDirection& direction, const std::vector<std::string>& coordinates);

}  // namespace mbd
