// The coordinate rates qdot(q, v) in the System's layout (body_state.hpp), written into the
// caller's vector: System::coordinate_rates returns a new vector, which an evaluation that
// must not allocate cannot use.
//   planar : qdot = v
//   spatial: Rdot = v_R,  pdot = 1/2 Gbar^T wbar   (book Eq. 8.48, Gbar of Eq. 8.44)
#pragma once

#include <mbd/sdk/body_state.hpp>
#include <mbd/sdk/rotation.hpp>

#include <Eigen/Core>

namespace mbd {

inline void write_coordinate_rates(Dimension dimension, const Eigen::VectorXd& q, const Eigen::VectorXd& v,
                                   Eigen::Ref<Eigen::VectorXd> qdot) {
    if (dimension == Dimension::Planar) {
        qdot = v;
        return;
    }
    for (Eigen::Index b = 0; b < v.size() / 6; ++b) {
        const Eigen::Index iq = 7 * b, iv = 6 * b;
        qdot.segment<3>(iq) = v.segment<3>(iv);
        const Vec4 p = q.segment<4>(iq + 3);
        qdot.segment<4>(iq + 3).noalias() = 0.5 * euler_Gbar(p).transpose() * v.segment<3>(iv + 3);
    }
}

}  // namespace mbd
