// Reactions an equilibrium does not determine (statics_analysis.hpp, StaticIndeterminacy).
#include <mbd/statics_analysis.hpp>

#include <mbd/mobility.hpp>

#include <Eigen/Dense>

#include <set>

namespace mbd {

namespace {

// The relative threshold of the ranks, as `mbd check`'s default (--rank-tolerance).
constexpr double kRankTolerance = 1e-9;

}  // namespace

StaticIndeterminacy resolve_indeterminacy(const Model& model, System& system, const State& state,
                                          Eigen::VectorXd& lambda) {
    StaticIndeterminacy out;
    out.redundant_rows = analyse_mobility(model, state, kRankTolerance).redundant;
    if (out.redundant_rows.empty()) return out;
    ConstraintValues cv;
    system.constraints(state, cv, true);  // joints, then drivers: the rows of lambda
    if (cv.J.rows() != lambda.size()) return out;
    const Eigen::MatrixXd Jt = Eigen::MatrixXd(cv.J).transpose();
    // the minimum-norm multipliers with the same constraint forces J^T lambda
    Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd> cod(Jt);
    cod.setThreshold(kRankTolerance);
    lambda = cod.solve(Eigen::VectorXd(Jt * lambda));
    // the self-stresses: an orthonormal basis of the null space of J^T
    Eigen::FullPivLU<Eigen::MatrixXd> lu(Jt);
    lu.setThreshold(kRankTolerance);
    const Eigen::MatrixXd kernel = lu.kernel();
    if (kernel.cols() == 0 || kernel.isZero()) return out;
    const Eigen::MatrixXd basis = Eigen::HouseholderQR<Eigen::MatrixXd>(kernel).householderQ() *
                                  Eigen::MatrixXd::Identity(kernel.rows(), kernel.cols());
    const ConstraintSystem rows(model, true);
    std::set<std::string> joints, drivers;
    for (Eigen::Index r = 0; r < basis.rows(); ++r) {
        if (basis.row(r).norm() <= 1e-6) continue;  // no self-stress loads this row
        const RowOwner& owner = rows.owner(static_cast<int>(r));
        std::set<std::string>& names = owner.kind == RowOwner::Kind::Driver ? drivers : joints;
        if (names.insert(owner.element_name).second)
            (owner.kind == RowOwner::Kind::Driver ? out.undetermined_drivers : out.undetermined_joints)
                .push_back(owner.element_name);
    }
    return out;
}

}  // namespace mbd
