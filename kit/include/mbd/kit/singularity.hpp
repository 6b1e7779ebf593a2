// Singular configurations, one rule for every formulation: a configuration is
// singular when the numerical rank of the constraint Jacobian J (joints and drivers)
// DROPS below its rank at the start of the run (book Sec. 3.9: a dead centre or a
// lock-up, where the velocities of the driven system are undetermined). Redundancy that
// is there from the start (e.g. the Bricard mechanism, permanently rank deficient) sets
// the reference rank lower and is not a singularity.
//
// Rank: column-pivoted Householder QR of J^T (its columns are J's rows, so the
// permutation names the dependent rows); a pivot counts when |R_kk| > tolerance * |R_00|.
// The formulations run the check once per accepted step (in project()), not per rhs.
// Cost: dense, O(nc^2 nv); the check is skipped for systems with nc * nv * min(nc, nv)
// above max_work (default 1e7 flops-ish, ~ 60 planar bodies with closed loops): large
// sparse systems rely on their factorization's own diagnostics (the augmented
// formulation's CHOLMOD minor / residual check, the partition's pivots).
//
// Two screens spare the QR on most steps; either one suffices, and both need a full reference
// rank.
// 1. A formulation that has just factored S = J M^-1 J^T at the accepted state passes the least
//    pivot of that factorization relative to its diagonal entry, rho: the squared sine of the
//    angle between a row of J and the rows before it, in the kinetic-energy metric. That metric
//    distorts angles by at most metric_distortion = sqrt(cond M) (set by the formulation), and
//    the QR's |R_kk| / |R_00| also scales with the rows' norms; so when
//        sqrt(rho) / metric_distortion * (least row norm / largest row norm) >= 10 tolerance,
//    no pivot of the QR can fall below the tolerance. Augmented and amalgamated pass the
//    velocity projection's factorization.
// 2. A FullRankCertificate the formulation lends the monitor (`certificate`): a lower bound on
//    sigma_min(J) / sigma_max(J), which bounds every |R_kk| / |R_00| from below; when it is
//    >= 10 tolerance the QR is skipped. It does not depend on M, so it serves where screen 1
//    cannot (a nearly singular inertia, cond M ~ 1e9) and formulations with no S of their own.
//    The formulations lend the sparse one of kit/include/mbd/kit/rank_certificate.hpp.
// Otherwise the QR decides. The recursive embedding does not call the check: on a tree the
// rows are independent by construction.
//
// Formulation key: singularity_tolerance (FormulationOptions::singularity_tolerance: relative,
// default 1e-5; 0 disables the check).
#pragma once

#include <mbd/kit/formulation.hpp>
#include <mbd/kit/system.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

namespace mbd {

// A certified lower bound on sigma_min(J) / sigma_max(J) at the checked state (0: none).
class FullRankCertificate {
public:
    virtual ~FullRankCertificate() = default;
    virtual double sigma_ratio_bound(const Eigen::SparseMatrix<double>& J) = 0;
};

class SingularityMonitor {
public:
    double tolerance = 1e-5;  // relative pivot tolerance of the rank test; 0 disables (FormulationOptions)
    double max_work = 1e7;    // skip above nc * nv * min(nc, nv)
    double metric_distortion = 1.0;  // sqrt(cond M) of the caller's metric (see the header)
    FullRankCertificate* certificate = nullptr;  // screen 2 of the header, when the caller has one

    // forget the reference rank (bind(): the next check sets it)
    void reset() { reference_ = -1; }
    int reference_rank() const { return reference_; }
    int qr_count() const { return qr_count_; }  // how many checks needed the QR (diagnostics)

    bool active(System& system) const {
        const double nc = system.constraint_rows(true) + system.velocity_constraint_rows(), nv = system.nv();
        return tolerance > 0.0 && nc > 0 && nc * nv * std::min(nc, nv) <= max_work;
    }

    // J at an accepted (projected) state at time t. The first call sets the reference
    // rank; a later call with a lower rank throws DynamicsError naming the dependent rows.
    // least_relative_pivot: of the caller's factorization of J M^-1 J^T at this state, or
    // 0 when it has none (see the header).
    void check(System& system, double t, const Eigen::SparseMatrix<double>& J, double least_relative_pivot = 0.0) {
        if (!active(system) || J.rows() == 0) return;
        if (reference_ == J.rows() && (screened_full_rank(J, least_relative_pivot) || certified_full_rank(J))) return;
        ++qr_count_;
        Jt_ = J.transpose();  // in place: Jt_ and qr_ keep their storage from call to call
        qr_.compute(Jt_);
        qr_.setThreshold(tolerance);
        const int rank = static_cast<int>(qr_.rank());
        if (reference_ < 0) {
            reference_ = rank;
            return;
        }
        if (rank >= reference_) return;
        const int nc = static_cast<int>(J.rows());
        const auto& perm = qr_.colsPermutation().indices();
        std::string rows;
        int listed = 0;
        for (int k = rank; k < nc && listed < 8; ++k, ++listed)
            rows += (rows.empty() ? "" : ", ") + system.describe_row(perm[k]);
        if (nc - rank > 8) rows += ", ...";
        char ranks[96];
        std::snprintf(ranks, sizeof ranks, "(rank %d < %d, relative tolerance %.3g)", rank, reference_, tolerance);
        throw DynamicsError(t, "singular configuration at t = " + format_time(t) +
                                   ": the constraint Jacobian lost rank " + ranks + "; joints involved: " + rows +
                                   "; the mechanism is at a dead centre or lock-up: drive another joint, or pass it "
                                   "with an implicit integrator / a driver that does not need the lost direction");
    }

private:
    bool certified_full_rank(const Eigen::SparseMatrix<double>& J) const {
        return certificate && certificate->sigma_ratio_bound(J) >= 10.0 * tolerance;
    }
    // the header's screen 1
    bool screened_full_rank(const Eigen::SparseMatrix<double>& J, double least_relative_pivot) {
        if (!(least_relative_pivot > 0.0)) return false;
        row_norms_.setZero(J.rows());
        for (int c = 0; c < J.outerSize(); ++c)
            for (Eigen::SparseMatrix<double>::InnerIterator it(J, c); it; ++it)
                row_norms_[it.row()] += it.value() * it.value();
        const double largest = row_norms_.maxCoeff(), least = row_norms_.minCoeff();
        if (!(largest > 0.0) || !(least > 0.0)) return false;
        return std::sqrt(least_relative_pivot * least / largest) / metric_distortion >= 10.0 * tolerance;
    }

    int reference_ = -1;
    int qr_count_ = 0;
    Eigen::VectorXd row_norms_;  // squared
    Eigen::MatrixXd Jt_;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

}  // namespace mbd
