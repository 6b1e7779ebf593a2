// Modes of a linearised system: see modes.hpp.
#include <mbd/modes.hpp>

#include <mbd/sdk/text.hpp>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>
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

// The column space (orthonormal) and the null space of X, singular values above
// tolerance counting as non-zero.
void column_and_null_space(const Eigen::MatrixXd& X, double tolerance, Eigen::MatrixXd& range, Eigen::MatrixXd& null) {
    if (X.size() == 0) {  // no rows or no columns: nothing spanned, every column direction null
        range.resize(X.rows(), 0);
        null = Eigen::MatrixXd::Identity(X.cols(), X.cols());
        return;
    }
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(X, Eigen::ComputeFullU | Eigen::ComputeFullV);
    int rank = 0;
    for (Eigen::Index i = 0; i < svd.singularValues().size(); ++i)
        if (svd.singularValues()[i] > tolerance) ++rank;
    range = svd.matrixU().leftCols(rank);
    null = svd.matrixV().rightCols(X.cols() - rank);
}

// Orthonormal basis (n x s) of the states on which A is nilpotent, the kernel of A^n:
// S_0 = {}, S_j = {x : A x in S_(j-1)}, until it stops growing.
Eigen::MatrixXd zero_eigenspace(const Eigen::MatrixXd& A, double tolerance) {
    const Eigen::Index n = A.rows();
    Eigen::MatrixXd S(n, 0), range, null;
    for (Eigen::Index step = 0; step <= n; ++step) {
        const Eigen::MatrixXd projected = A - S * (S.transpose() * A);  // (I - S S^T) A
        column_and_null_space(projected, tolerance, range, null);
        if (null.cols() == S.cols()) return null;
        S = null;
    }
    return S;
}

// The basis rows brought to reduced row-echelon form: each direction has a pivot entry 1 and
// zeros at the others' pivots (so that a single ignorable coordinate reads as itself).
std::vector<IgnorableDirection> echelon(const Eigen::MatrixXd& S, const Eigen::MatrixXd& joint_map) {
    Eigen::MatrixXd R = S.transpose();  // s x kz
    std::vector<IgnorableDirection> out;
    std::vector<char> used(R.cols(), 0);
    std::vector<Eigen::Index> pivots;
    for (Eigen::Index r = 0; r < R.rows(); ++r) {
        Eigen::Index p = 0;
        double best = -1.0;
        for (Eigen::Index c = 0; c < R.cols(); ++c)
            if (!used[c] && std::abs(R(r, c)) > best) best = std::abs(R(r, c)), p = c;
        used[p] = 1;
        pivots.push_back(p);
        R.row(r) /= R(r, p);
        for (Eigen::Index o = 0; o < R.rows(); ++o)
            if (o != r) R.row(o) -= R(o, p) * R.row(r);
    }
    for (Eigen::Index r = 0; r < R.rows(); ++r) {
        IgnorableDirection d;
        d.shape = R.row(r).transpose();
        for (Eigen::Index c = 0; c < d.shape.size(); ++c)
            if (std::abs(d.shape[c]) < 1e-8) d.shape[c] = 0.0;  // the differences' noise
        d.coordinate = static_cast<int>(pivots[r]);
        d.shape[d.coordinate] = 1.0;
        d.single = (d.shape.array() != 0.0).count() == 1;
        d.joint_shape = joint_map * d.shape;
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


// The characteristic polynomial det(lambda I - A) = sum_k c_k lambda^k (c_n = 1), from the
// upper Hessenberg form H = Q^T A Q (a backward-stable reduction) by the recurrence of its
// leading principal minors, p_k = (lambda - h_kk) p_(k-1) - sum_(i<k) h_ik (h_(i+1,i)...h_(k,k-1)) p_(i-1)
// (Wilkinson, The Algebraic Eigenvalue Problem, Sec. 7.11).
Eigen::VectorXd characteristic_polynomial(const Eigen::MatrixXd& A) {
    const Eigen::Index n = A.rows();
    const Eigen::MatrixXd H = Eigen::HessenbergDecomposition<Eigen::MatrixXd>(A).matrixH();
    std::vector<Eigen::VectorXd> p(n + 1);  // p[k]: coefficients of p_k, ascending powers
    p[0] = Eigen::VectorXd::Ones(1);
    for (Eigen::Index k = 1; k <= n; ++k) {
        p[k] = Eigen::VectorXd::Zero(k + 1);
        p[k].tail(k) = p[k - 1];                   // lambda p_(k-1)
        p[k].head(k) -= H(k - 1, k - 1) * p[k - 1];
        double product = 1.0;
        for (Eigen::Index i = k - 1; i >= 1; --i) {
            product *= H(i, i - 1);
            p[k].head(i) -= H(i - 1, k - 1) * product * p[i - 1];
        }
    }
    return p[n];
}

// An eigenvalue of the reduced matrix polished as the nearest root of q(lambda) =
// det(lambda I - A) / lambda^s, s the dimension of the zero eigenspace set apart. Why: the
// differences leave A's zero eigenvalues a cluster of size ~eps^(1/s) (a nilpotent block is
// that sensitive), and an eigenvalue near the cluster (a bicycle's capsize mode at its
// critical speed) is pulled by it; q's coefficients are polynomials in A's entries, so their
// error is that of A only. Newton's method from the reduced eigenvalue; kept when it
// converges close by.
std::complex<double> polished(std::complex<double> lambda, const Eigen::VectorXd& q) {
    std::complex<double> x = lambda, step = 0.0;
    for (int iteration = 0; iteration < 30; ++iteration) {
        std::complex<double> value = 0.0, slope = 0.0;
        for (Eigen::Index k = q.size() - 1; k >= 0; --k) {  // Horner, with the derivative
            slope = slope * x + value;
            value = value * x + q[k];
        }
        if (slope == 0.0) break;
        step = value / slope;
        x -= step;
        if (std::abs(step) <= 1e-15 * std::max(1.0, std::abs(x))) break;  // at the round-off of q
    }
    const double scale = std::max(1.0, std::abs(lambda));
    const bool converged = std::isfinite(std::abs(x)) && std::abs(step) <= 1e-11 * scale;
    return converged && std::abs(x - lambda) <= 1e-6 * scale ? x : lambda;
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


// The zero eigenvalues are set apart first: on their eigenspace S (the kernel of A^n) A is
// nilpotent, and in a basis [S, C] (C its orthogonal complement) A is block triangular, so
// that the eigenvalues of C^T A C are the others. The position parts of S are the ignorable
// directions (a coordinate the dynamics do not depend on, or the heading, whose rate only
// moves such a coordinate); S's states with no position part are free velocities (a
// neighbouring steady motion: a free body's speed, a bicycle's forward speed), each a mode
// with lambda = 0 whose shape is the position rates it gives.
ModeAnalysis modes_of(const LinearModel& linear, double ignorable_tolerance) {
    ModeAnalysis out;
    const Eigen::MatrixXd& A = linear.A;
    const int n = static_cast<int>(A.rows());
    const int kz = static_cast<int>(linear.coordinates.size());
    const double scale = A.size() ? A.cwiseAbs().maxCoeff() : 0.0;
    const double tolerance = ignorable_tolerance * std::max(scale, 1e-300);
    const Eigen::MatrixXd S = zero_eigenspace(A, tolerance);
    Eigen::MatrixXd positions, free_velocities;
    column_and_null_space(S.topRows(kz), 1e-8, positions, free_velocities);
    out.ignorable = echelon(positions, linear.joint_map);
    const Eigen::MatrixXd position_rates = A.topRows(kz);
    for (Eigen::Index c = 0; c < free_velocities.cols(); ++c) {
        out.modes.push_back(make_mode(0.0, false, (position_rates * (S * free_velocities.col(c))).cast<std::complex<double>>(),
                                      linear.joint_map));
        out.modes.back().free_velocity = true;
    }
    Eigen::MatrixXd C = Eigen::MatrixXd::Identity(n, n);
    if (S.cols() > 0) {
        const Eigen::JacobiSVD<Eigen::MatrixXd> svd(S, Eigen::ComputeFullU);
        C = svd.matrixU().rightCols(n - S.cols());
    }
    const Eigen::MatrixXd reduced = C.transpose() * A * C;
    if (reduced.size() > 0) {
        const Eigen::EigenSolver<Eigen::MatrixXd> eigen(reduced, true);
        Eigen::VectorXcd lambda = eigen.eigenvalues();
        if (S.cols() > 0) {
            const Eigen::VectorXd q = characteristic_polynomial(A).tail(n + 1 - S.cols());  // c_s .. c_n
            for (Eigen::Index i = 0; i < lambda.size(); ++i) lambda[i] = polished(lambda[i], q);
        }
        const Eigen::MatrixXcd vectors = C.cast<std::complex<double>>() * eigen.eigenvectors();
        const double zero = 1e-12 * std::max(1.0, scale);
        for (Eigen::Index i = 0; i < lambda.size(); ++i) {
            if (lambda[i].imag() < -zero) continue;  // its conjugate stands for the pair
            out.modes.push_back(make_mode(lambda[i], lambda[i].imag() > zero, vectors.col(i).head(kz), linear.joint_map));
        }
    }
    std::stable_sort(out.modes.begin(), out.modes.end(), [](const Mode& a, const Mode& b) {
        return a.natural_frequency < b.natural_frequency;
    });
    return out;
}

}  // namespace mbd
