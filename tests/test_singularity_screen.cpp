// Issue 13: the singular-configuration check (sdk singularity.hpp) skips its QR of J^T when the
// caller's own factorization of S = J M^-1 J^T certifies that the rows are well independent,
// and still finds the rank drop at a dead centre. Oracles: the dead centre of the slider crank
// driven at its slider (book Sec. 3.9: crank and rod aligned, the driver's row dependent on the
// joints'), where S must be (nearly) singular; a regular position, where it is not.
#include "support/test_support.hpp"

#include <mbd/model_system.hpp>
#include <mbd/sdk/block_mass_inverse.hpp>
#include <mbd/sdk/dense_gram.hpp>
#include <mbd/sdk/singularity.hpp>

#include <gtest/gtest.h>

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

}  // namespace
