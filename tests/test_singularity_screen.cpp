// Issue 13: the singular-configuration check (kit singularity.hpp) skips its QR of J^T when the
// caller's own factorization of S = J M^-1 J^T, or the sparse certificate of J J^T
// (kit/include/mbd/kit/rank_certificate.hpp), shows that the rows are well independent, and
// still finds the rank drop at a dead centre. The certificate's bound is checked against
// sigma_min / sigma_max of J by a dense SVD. Oracles: the dead centre of the slider crank
// driven at its slider (book Sec. 3.9: crank and rod aligned, the driver's row dependent on the
// joints'), where S must be (nearly) singular; a regular position, where it is not.
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/kit/block_mass_inverse.hpp>
#include <mbd/kit/dense_gram.hpp>
#include <mbd/kit/singularity.hpp>

#include <mbd/kit/rank_certificate.hpp>

#include <Eigen/SVD>

#include <gtest/gtest.h>

#include <random>

namespace {

struct DeadCentre : ::testing::Test {
    const mbd::Model model = mbd::test::load("extreme/slider-crank-dead-centre.yaml");
    mbd::ModelSystem system{model};
    mbd::BlockMassInverse mass_inverse;
    mbd::DenseGram gram;
    mbd::ConstraintValues cv;

    void SetUp() override {
        mass_inverse.bind(system, "test");
        gram.resize(system.constraint_rows(true), system.nv());
    }
    // J and the least relative pivot of S at the state
    double relative_pivot_at(const mbd::State& state) {
        system.constraints(state, cv, true);
        gram.factor(cv.J, mass_inverse);
        return gram.least_relative_pivot();
    }
    // J at the assembled initial state (a regular position), and a certificate lent to `monitor`
    void bind_at_the_start(mbd::SingularityMonitor& monitor, mbd::RankCertificate& certificate) {
        mbd::State start = system.initial_state();
        system.assemble(start, true);
        system.constraints(start, cv, true);
        certificate.bind(system, monitor);
    }
    // crank (0.2 m) and rod (0.4 m) aligned along +x: the dead centre, slider at x = 0.6
    mbd::State dead_centre() const {
        mbd::State state = system.initial_state();
        state.t = 0.5;  // the driver's s(0.5) puts the slider at x = 0.6
        state.q << 0.1, 0.0, 0.0, 0.4, 0.0, 0.0, 0.6, 0.0, 0.0;
        state.v.setZero();
        return state;
    }
};

TEST_F(DeadCentre, TheScreenSkipsTheQrOnlyWhereTheRowsAreWellIndependent) {
    mbd::State start = system.initial_state();
    system.assemble(start, true);
    const double regular = relative_pivot_at(start);
    ASSERT_GT(regular, 1e-3) << "the crank at 45 degrees is far from the dead centre";

    mbd::SingularityMonitor monitor;
    monitor.metric_distortion = mass_inverse.distortion();
    monitor.check(system, 0.0, cv.J, regular);  // sets the reference rank: always a QR
    EXPECT_EQ(monitor.reference_rank(), system.constraint_rows(true));
    EXPECT_EQ(monitor.qr_count(), 1);
    monitor.check(system, 0.0, cv.J, regular);
    EXPECT_EQ(monitor.qr_count(), 1) << "a certified full rank needs no QR";
    monitor.check(system, 0.0, cv.J, 0.0);
    EXPECT_EQ(monitor.qr_count(), 2) << "without a factorization the QR decides";
    monitor.metric_distortion = 1e8;  // a metric that could hide a near dependence
    monitor.check(system, 0.0, cv.J, regular);
    EXPECT_EQ(monitor.qr_count(), 3);

    // at the dead centre the factorization cannot certify anything, and the QR finds the drop
    monitor.metric_distortion = mass_inverse.distortion();
    const double singular = relative_pivot_at(dead_centre());
    EXPECT_LT(singular, 1e-10);
    EXPECT_THROW(monitor.check(system, 0.5, cv.J, singular), mbd::DynamicsError);
    EXPECT_EQ(monitor.qr_count(), 4);
}

// sigma_min / sigma_max of J, the quantity the certificate bounds from below
double sigma_ratio(const Eigen::SparseMatrix<double>& J) {
    const Eigen::VectorXd sigma = Eigen::JacobiSVD<Eigen::MatrixXd>(Eigen::MatrixXd(J)).singularValues();
    return sigma.minCoeff() / sigma.maxCoeff();
}

TEST_F(DeadCentre, TheCertificateSkipsTheQrAwayFromTheDeadCentreAndNotAtIt) {
    mbd::SingularityMonitor monitor;
    mbd::RankCertificate certificate;
    bind_at_the_start(monitor, certificate);
    ASSERT_EQ(monitor.certificate, &certificate);
    const double bound = certificate.sigma_ratio_bound(cv.J), exact = sigma_ratio(cv.J);
    EXPECT_LE(bound, exact);
    EXPECT_GE(bound, exact / 100.0) << "a bound too loose to spare any QR";
    monitor.check(system, 0.0, cv.J);  // the reference rank: always a QR
    monitor.check(system, 0.0, cv.J);
    EXPECT_EQ(monitor.qr_count(), 1) << "the certificate spares the QR at the regular position";

    system.constraints(dead_centre(), cv, true);
    EXPECT_LT(certificate.sigma_ratio_bound(cv.J), 10.0 * monitor.tolerance);
    EXPECT_THROW(monitor.check(system, 0.5, cv.J), mbd::DynamicsError);
    EXPECT_EQ(monitor.qr_count(), 2);
}

// The certificate's bound on J at a scene's assembled initial state, and sigma_min / sigma_max
struct BoundAndExact {
    double bound, exact;
};
BoundAndExact certified_at_the_start(const char* scene) {
    const mbd::Model model = mbd::test::load(scene);
    mbd::ModelSystem system{model};
    mbd::State state = system.initial_state();
    system.assemble(state, true);
    mbd::ConstraintValues cv;
    system.constraints(state, cv, true);
    mbd::SingularityMonitor monitor;
    monitor.max_work = 1e12;  // lend the certificate whatever the size
    mbd::RankCertificate certificate;
    certificate.bind(system, monitor);
    return {certificate.sigma_ratio_bound(cv.J), sigma_ratio(cv.J)};
}

// The bound is below the exact ratio and within a factor 100 of it on mechanisms of both
// dimensions, including rods whose axial inertia makes the kinetic-energy screen useless
// (cond M ~ 1e10), a driven loop and a 200-link chain; a J with redundant rows has none.
TEST(RankCertificate, BoundsSigmaMinOverSigmaMaxFromBelow) {
    for (const char* scene : {"extreme/spatial-chain-50.yaml", "extreme/slider-crank-dead-centre.yaml",
                              "extreme/car-axis-published.yaml", "extreme/flyball-stiff.yaml",
                              "extreme/chain-200.yaml"}) {
        SCOPED_TRACE(scene);
        const BoundAndExact r = certified_at_the_start(scene);
        EXPECT_GT(r.bound, 0.0);
        EXPECT_LE(r.bound, r.exact);
        EXPECT_GE(r.bound, r.exact / 100.0);
    }
    const BoundAndExact bricard = certified_at_the_start("extreme/bricard-dynamics.yaml");
    EXPECT_LT(bricard.exact, 1e-12) << "the Bricard's sixth joint is redundant";
    EXPECT_LT(bricard.bound, 10.0 * mbd::SingularityMonitor().tolerance) << "no certificate of full rank";
}

// Between factorizations the certificate answers from its anchor by Weyl's inequality. Along a
// path of assembled states (positions moved a little each time, as between steps) the answer
// stays below sigma_min / sigma_max (dense SVD) at every state, also after a large last move,
// and most states need no factorization; at the dead centre, reached from an anchor at a
// regular position, nothing is certified and G is factored afresh.
TEST(RankCertificate, AnAnchorAnswersSmallMovesBelowTheExactRatio) {
    // (not the driven slider crank: assembly at t = 0 puts every move back where it started)
    for (const char* scene : {"extreme/spatial-chain-50.yaml", "extreme/car-axis-published.yaml",
                              "extreme/flyball-stiff.yaml"}) {
        SCOPED_TRACE(scene);
        const mbd::Model model = mbd::test::load(scene);
        mbd::ModelSystem system{model};
        mbd::State state = system.initial_state();
        system.assemble(state, true);
        mbd::ConstraintValues cv;
        mbd::SingularityMonitor monitor;
        monitor.max_work = 1e12;
        mbd::RankCertificate certificate;
        certificate.bind(system, monitor);
        std::mt19937 rng(3);
        std::normal_distribution<double> normal;
        Eigen::VectorXd direction(state.q.size());
        for (Eigen::Index k = 0; k < direction.size(); ++k) direction[k] = normal(rng);
        direction /= direction.norm();
        const int calls = 40;
        double worst = 0.0;  // bound / exact, at most 1
        for (int k = 0; k < calls; ++k) {
            mbd::State moved = state;
            moved.q += (k < calls - 1 ? 1e-4 * k : 0.3) * direction;  // the last: a large move
            system.assemble(moved, true);
            system.constraints(moved, cv, true);
            const double bound = certificate.sigma_ratio_bound(cv.J), exact = sigma_ratio(cv.J);
            EXPECT_LE(bound, exact) << "state " << k;
            EXPECT_GT(bound, 0.0) << "state " << k;
            worst = std::max(worst, bound / exact);
        }
        std::printf("%s: %ld factorizations for %d calls, largest bound / exact %.3f\n", scene,
                    certificate.factorizations(), calls, worst);
        EXPECT_LE(certificate.factorizations(), calls / 4);
    }
}

TEST_F(DeadCentre, AnAnchorAtTheRegularPositionCertifiesNothingAtTheDeadCentre) {
    mbd::SingularityMonitor monitor;
    mbd::RankCertificate certificate;
    bind_at_the_start(monitor, certificate);
    EXPECT_GT(certificate.sigma_ratio_bound(cv.J), 10.0 * monitor.tolerance);
    system.constraints(dead_centre(), cv, true);
    EXPECT_LT(certificate.sigma_ratio_bound(cv.J), 10.0 * monitor.tolerance);
    EXPECT_EQ(certificate.factorizations(), 2) << "the anchor's bound fell: factored afresh";
}

}  // namespace
