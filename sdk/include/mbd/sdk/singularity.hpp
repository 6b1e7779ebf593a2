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
// Formulation key: singularity_tolerance (FormulationOptions::singularity_tolerance: relative,
// default 1e-5; 0 disables the check).
#pragma once

#include <mbd/sdk/formulation.hpp>
#include <mbd/sdk/system.hpp>
#include <mbd/sdk/text.hpp>

#include <Eigen/Dense>
#include <Eigen/SparseCore>

#include <algorithm>
#include <cstdio>
#include <string>

namespace mbd {

class SingularityMonitor {
public:
    double tolerance = 1e-5;  // relative pivot tolerance of the rank test; 0 disables (FormulationOptions)
    double max_work = 1e7;    // skip above nc * nv * min(nc, nv)

    // forget the reference rank (bind(): the next check sets it)
    void reset() { reference_ = -1; }
    int reference_rank() const { return reference_; }

    bool active(System& system) const {
        const double nc = system.constraint_rows(true), nv = system.nv();
        return tolerance > 0.0 && nc > 0 && nc * nv * std::min(nc, nv) <= max_work;
    }

    // J at an accepted (projected) state at time t. The first call sets the reference
    // rank; a later call with a lower rank throws DynamicsError naming the dependent rows.
    void check(System& system, double t, const Eigen::SparseMatrix<double>& J) {
        if (!active(system) || J.rows() == 0) return;
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
    int reference_ = -1;
    Eigen::MatrixXd Jt_;
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr_;
};

}  // namespace mbd
