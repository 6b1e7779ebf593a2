#include "modal_model.hpp"

namespace mbd::ffrf {

namespace {
Eigen::Matrix2d rotation_generator() {  // P: dA/dtheta = A P, P u = u turned by +90 degrees
    Eigen::Matrix2d P;
    P << 0, -1, 1, 0;
    return P;
}
}  // namespace

ModalModel::ModalModel(int m)
    : modes(m), Sbar(Matrix2X::Zero(2, m)), I0f(Eigen::RowVectorXd::Zero(m)), I0Pf(Eigen::RowVectorXd::Zero(m)),
      Mff(Eigen::MatrixXd::Zero(m, m)), Stilde(Eigen::MatrixXd::Zero(m, m)), Kff(Eigen::MatrixXd::Zero(m, m)) {}

void ModalModel::add_mass(double dm, const ModalPoint& point) {
    const Eigen::Matrix2d P = rotation_generator();
    mass += dm;
    S0 += dm * point.u0;
    I00 += dm * point.u0.squaredNorm();
    Sbar += dm * point.S;
    I0f += dm * point.u0.transpose() * point.S;
    I0Pf += dm * (P * point.u0).transpose() * point.S;
    Mff += dm * point.S.transpose() * point.S;
    Stilde += dm * point.S.transpose() * P * point.S;
}

}  // namespace mbd::ffrf
