// Modes of a linearised system: see modes.hpp.
#include <mbd/modes.hpp>

#include "analyses/cyclic_directions.hpp"

#include <mbd/sdk/text.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/SVD>

#include <algorithm>
#include <cmath>

namespace mbd {

namespace {

// Largest component 1 (the phase of a complex shape fixed by it).
Eigen::VectorXcd normalised(const Eigen::VectorXcd& x) {
    Eigen::Index largest = 0;
    if (x.size() == 0) return x;
    x.cwiseAbs().maxCoeff(&largest);
    return std::abs(x[largest]) > 0.0 ? Eigen::VectorXcd(x / x[largest]) : x;
}

// The cyclic directions of linearisation.hpp, named by their pivot coordinates.
std::vector<IgnorableDirection> ignorable_directions(const LinearModel& linear) {
    std::vector<IgnorableDirection> out;
    for (Eigen::Index c = 0; c < linear.cyclic.cols(); ++c) {
        IgnorableDirection d;
        d.shape = linear.cyclic.col(c);
        d.coordinate = linear.cyclic_pivots[c];
        d.single = (d.shape.array() != 0.0).count() == 1;
        d.joint_shape = linear.joint_map * d.shape;
        out.push_back(d);
    }
    return out;
}

Mode make_mode(std::complex<double> eigenvalue, bool oscillatory, const Eigen::VectorXcd& shape,
               const Eigen::MatrixXd& joint_map) {
    Mode m;
    m.oscillatory = oscillatory;
    m.eigenvalue = oscillatory ? eigenvalue : std::complex<double>(eigenvalue.real(), 0.0);
    m.natural_frequency = std::abs(m.eigenvalue);
    m.damped_frequency = std::abs(m.eigenvalue.imag());
    m.damping_ratio = m.natural_frequency > 0.0 ? -m.eigenvalue.real() / m.natural_frequency : 0.0;
    m.shape = normalised(shape);
    m.joint_shape = joint_map.cast<std::complex<double>>() * m.shape;
    return m;
}


}  // namespace

std::string describe(const IgnorableDirection& direction, const std::vector<std::string>& coordinates) {
    std::string out = coordinates[direction.coordinate];
    for (Eigen::Index c = 0; c < direction.shape.size(); ++c) {
        const double x = direction.shape[c];
        if (c == direction.coordinate || x == 0.0) continue;
        out += (x < 0 ? " - " : " + ") + format_number(std::abs(x), 6) + " " + coordinates[c];
    }
    return out;
}


// The states of the cyclic directions S (linearisation.hpp: each shift with the velocities it
// carries) span an invariant subspace of A on which it is nilpotent (a cyclic shift changes only
// cyclic positions' rates); the free velocities F are the velocity directions whose rates all lie
// in it (a neighbouring steady motion: a free body's speed, a bicycle's forward speed), each a
// mode with lambda = 0 whose shape is the position rates it gives. S + F is invariant too, so in
// a basis [S F C] (C the orthonormal complement) A is block triangular and the eigenvalues of
// C^T A C are all the others, each reported, however close to zero (A's entries in the rows
// of C and the columns of S + F are the differences' round-off, dropped with the block).
ModeAnalysis modes_of(const LinearModel& linear, double free_tolerance) {
    ModeAnalysis out;
    const Eigen::MatrixXd& A = linear.A;
    const int n = static_cast<int>(A.rows());
    const int kz = static_cast<int>(linear.coordinates.size());
    const int kw = n - kz;
    out.ignorable = ignorable_directions(linear);
    Eigen::MatrixXd set_apart(n, linear.cyclic.cols());  // the states of the cyclic directions
    if (linear.cyclic.cols() > 0) {
        Eigen::MatrixXd states(n, linear.cyclic.cols());
        states << linear.cyclic, linear.carried_velocities * linear.cyclic;
        set_apart = orthonormal_basis(states);
    }
    // velocity directions whose every rate lies in S, against the velocity columns' own scale
    Eigen::MatrixXd changes = A.rightCols(kw);
    const double velocity_scale = changes.size() ? changes.cwiseAbs().maxCoeff() : 0.0;
    changes -= set_apart * (set_apart.transpose() * changes);
    const Eigen::MatrixXd free_velocities = null_space(changes, free_tolerance * std::max(velocity_scale, 1e-300));
    for (Eigen::Index c = 0; c < free_velocities.cols(); ++c) {
        out.modes.push_back(make_mode(0.0, false,
                                      (A.block(0, kz, kz, kw) * free_velocities.col(c)).cast<std::complex<double>>(),
                                      linear.joint_map));
        out.modes.back().free_velocity = true;
    }
    if (free_velocities.cols() > 0) {  // (an empty block of an empty matrix is undefined in Eigen)
        set_apart.conservativeResizeLike(Eigen::MatrixXd::Zero(n, set_apart.cols() + free_velocities.cols()));
        set_apart.bottomRightCorner(kw, free_velocities.cols()) = free_velocities;
    }
    Eigen::MatrixXd C = Eigen::MatrixXd::Identity(n, n);
    if (set_apart.cols() > 0) {
        const Eigen::JacobiSVD<Eigen::MatrixXd> svd(set_apart, Eigen::ComputeFullU);
        C = svd.matrixU().rightCols(n - set_apart.cols());
    }
    const Eigen::MatrixXd reduced = C.transpose() * A * C;
    if (reduced.size() > 0) {
        const Eigen::EigenSolver<Eigen::MatrixXd> eigen(reduced, true);
        const Eigen::VectorXcd lambda = eigen.eigenvalues();
        const Eigen::MatrixXcd vectors = C.cast<std::complex<double>>() * eigen.eigenvectors();
        for (Eigen::Index i = 0; i < lambda.size(); ++i) {
            // a complex pair is shown by its member with Im > 0 (EigenSolver gives exact conjugates)
            if (lambda[i].imag() < 0.0) continue;
            out.modes.push_back(make_mode(lambda[i], lambda[i].imag() > 0.0, vectors.col(i).head(kz), linear.joint_map));
        }
    }
    std::stable_sort(out.modes.begin(), out.modes.end(), [](const Mode& a, const Mode& b) {
        return a.natural_frequency < b.natural_frequency;
    });
    return out;
}

}  // namespace mbd
