// Mobility analysis: the Gruebler count (coordinates minus joint equations,
// book Sec. 3.1) against the rank of the joint Jacobian C_q at a configuration
// (book Ex. 2.12: the independent equations are those that keep the rank
// growing). The two differ when some joint equations are redundant (a planar
// four-bar modelled with spatial joints, the Bricard linkage); the redundant
// rows are found incrementally, in row order: a row is redundant when it lies in
// the span of the rows before it.
#include <mbd/mobility.hpp>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>

namespace mbd {

MobilityReport analyse_mobility(const Model& model, const State& state, double rank_tolerance) {
    const ConstraintSystem system(model, false);
    MobilityReport report;
    report.coordinates = model.nv();
    report.constraint_rows = system.joint_rows();
    report.driver_rows = static_cast<int>(model.drivers.size());
    report.gruebler_dof = report.coordinates - report.constraint_rows;
    report.rank = 0;
    report.rank_dof = report.coordinates;
    for (const JointInstance& j : model.joints) report.velocity_rows += j.joint->velocity_rows();
    report.velocity_dof = report.coordinates;
    if (report.coordinates == 0) return report;
    State s = state;
    if (s.v.size() != model.nv()) s.v = Eigen::VectorXd::Zero(model.nv());
    Data data(model);
    if (report.velocity_rows > 0) {
        ConstraintValues all;
        ConstraintSystem(model, false, true).evaluate(s, data, all);
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr{Eigen::MatrixXd(all.J)};
        qr.setThreshold(rank_tolerance);
        report.velocity_dof = report.coordinates - static_cast<int>(qr.rank());
    }
    if (system.rows() == 0) return report;

    ConstraintValues values;
    system.evaluate(s, data, values);
    const Eigen::MatrixXd J(values.J);

    // rank by column-pivoting Householder QR with a relative threshold
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(J);
    qr.setThreshold(rank_tolerance);
    report.rank = static_cast<int>(qr.rank());
    report.rank_dof = report.coordinates - report.rank;

    // Incremental redundancy: Gram-Schmidt (twice, for orthogonality) of each
    // row against an orthonormal basis of the independent rows before it.
    double scale = 0.0;
    for (int r = 0; r < J.rows(); ++r) scale = std::max(scale, J.row(r).norm());
    const double threshold = rank_tolerance * std::max(scale, 1e-300);
    Eigen::MatrixXd basis(J.cols(), std::min<Eigen::Index>(J.rows(), J.cols()));
    int independent = 0;
    std::vector<int> redundant_rows;
    for (int r = 0; r < J.rows(); ++r) {
        Eigen::VectorXd w = J.row(r).transpose();
        for (int pass = 0; pass < 2 && independent > 0; ++pass) {
            const auto Q = basis.leftCols(independent);
            w -= Q * (Q.transpose() * w);
        }
        const double norm = w.norm();
        if (norm <= threshold || independent == basis.cols()) {
            redundant_rows.push_back(r);
        } else {
            basis.col(independent++) = w / norm;
        }
    }

    // The QR rank is the one reported. The incremental count agrees with it
    // except for a row whose independent part sits within round-off of the
    // threshold; such a model is near a singular configuration anyway.
    for (int r : redundant_rows) report.redundant.push_back(system.owner(r));
    return report;
}

}  // namespace mbd
