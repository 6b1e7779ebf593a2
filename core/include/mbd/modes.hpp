// Modes of a linearised system (issue 17): eigenvalues of A, natural frequencies, damping
// ratios and mode shapes in the independent and joint coordinates; coordinates on which
// the equations of motion do not depend (ignorable, cyclic: position on the ground, heading,
// a wheel's spin angle; found from the equations, linearisation.hpp) are set apart with their
// zero eigenvalues. Every other eigenvalue is reported, however close to zero (issue 42).
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

// A cyclic direction of the independent positions (LinearModel::cyclic): the equations of
// motion do not depend on it; the position on the ground, a wheel's spin angle, or the
// heading of a bicycle, whose rate moves only its lateral position. Each has eigenvalue zero.
// Never inferred from an eigenvalue's size: a mode that is only neutral (lambda = 0 or near
// it: a bicycle's capsize mode at its critical speed, a disc's steady turn) is a Mode.
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

// The ignorable directions are linear.cyclic; free velocities (a velocity direction whose
// rates all lie in the span of the cyclic directions' states) are found with singular values
// below free_tolerance * max|A's velocity columns| counting as zero (their own scale: a
// flexible body's stiffness puts entries 1e9 times larger in the position columns); every other eigenvalue is one of C^T A C,
// C the orthonormal complement of the two (A is block triangular in that basis).
ModeAnalysis modes_of(const LinearModel& linear, double free_tolerance = 1e-8);

// "frame.x" for a single coordinate, "frame.rz + 0.35 fork.rz" for a combination.
std::string describe(const IgnorableDirection& direction, const std::vector<std::string>& coordinates);

}  // namespace mbd
