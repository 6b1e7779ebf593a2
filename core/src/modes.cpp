// Modes of a linearised system: see modes.hpp.
#include <mbd/modes.hpp>

#include <Eigen/Eigenvalues>

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

}  // namespace

ModeAnalysis modes_of(const LinearModel& linear, double ignorable_tolerance) {
    ModeAnalysis out;
    const Eigen::MatrixXd& A = linear.A;
    const int k = static_cast<int>(A.rows()) / 2;
    const double scale = A.size() ? A.cwiseAbs().maxCoeff() : 0.0;
    std::vector<int> kept;  // states of A without the ignorable positions
    for (int c = 0; c < k; ++c) {
        if (A.col(c).cwiseAbs().maxCoeff() <= ignorable_tolerance * scale) out.ignorable.push_back(c);
        else kept.push_back(c);
    }
    const int positions = static_cast<int>(kept.size());
    for (int c = 0; c < k; ++c) kept.push_back(k + c);
    // Removing an ignorable position's row and column leaves the other eigenvalues: nothing
    // depends on it (its column is zero), and its own eigenvalue is the zero set apart.
    Eigen::MatrixXd reduced(kept.size(), kept.size());
    for (size_t j = 0; j < kept.size(); ++j)
        for (size_t i = 0; i < kept.size(); ++i) reduced(i, j) = A(kept[i], kept[j]);
    if (reduced.size() == 0) return out;
    const Eigen::EigenSolver<Eigen::MatrixXd> eigen(reduced, true);
    const Eigen::VectorXcd lambda = eigen.eigenvalues();
    const Eigen::MatrixXcd vectors = eigen.eigenvectors();
    const double zero = 1e-12 * std::max(1.0, scale);
    for (Eigen::Index i = 0; i < lambda.size(); ++i) {
        const std::complex<double> l = lambda[i];
        if (l.imag() < -zero) continue;  // its conjugate stands for the pair
        Mode m;
        m.oscillatory = l.imag() > zero;
        m.eigenvalue = m.oscillatory ? l : std::complex<double>(l.real(), 0.0);
        m.natural_frequency = std::abs(m.eigenvalue);
        m.damped_frequency = std::abs(m.eigenvalue.imag());
        m.damping_ratio = m.natural_frequency > 0.0 ? -m.eigenvalue.real() / m.natural_frequency : 0.0;
        // position part of the eigenvector, back on all k independent coordinates; a mode
        // with no position part (a free velocity, lambda = 0) keeps its velocity part
        Eigen::VectorXcd shape = Eigen::VectorXcd::Zero(k);
        for (int p = 0; p < positions; ++p) shape[kept[p]] = vectors(p, i);
        if (shape.cwiseAbs().maxCoeff() <= 1e-12 * vectors.col(i).cwiseAbs().maxCoeff())
            for (int c = 0; c < k; ++c) shape[c] = vectors(positions + c, i);
        m.shape = normalised(shape);
        m.joint_shape = linear.joint_map.cast<std::complex<double>>() * m.shape;
        out.modes.push_back(m);
    }
    std::stable_sort(out.modes.begin(), out.modes.end(), [](const Mode& a, const Mode& b) {
        return a.natural_frequency < b.natural_frequency;
    });
    return out;
}

}  // namespace mbd
