// A force plugin that gives no Jacobians (quadratic air drag on each body's
// mass centre, F = -c |v| v): the core must then differentiate it numerically.
// Test-only.
#include <mbd/sdk/plugin.hpp>

namespace {

class QuadraticDrag : public mbd::Force {
public:
    QuadraticDrag(mbd::Dimension dimension, double c) : dimension_(dimension), c_(c) {}
    void evaluate(const mbd::BodyStates& bodies, Eigen::Ref<Eigen::VectorXd> Q) const override {
        const int nvb = mbd::velocities_per_body(dimension_);
        for (int k = 0; k < bodies.size(); ++k) {
            if (dimension_ == mbd::Dimension::Planar) {
                const mbd::Vec2 v = bodies.planar(k).Rdot;
                Q.segment<2>(nvb * k) -= c_ * v.norm() * v;
            } else {
                const mbd::Vec3 v = bodies.spatial(k).Rdot;
                Q.segment<3>(nvb * k) -= c_ * v.norm() * v;
            }
        }
    }

private:
    mbd::Dimension dimension_;
    double c_;
};

std::unique_ptr<mbd::Force> make_drag(const mbd::ForceSpec& spec) {
    return std::make_unique<QuadraticDrag>(spec.dimension, spec.params.number("coefficient"));
}

}  // namespace

MBD_FORCE_PLUGIN(quadratic_drag, make_drag)
