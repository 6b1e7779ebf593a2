#include <mbd/model.hpp>

namespace mbd {

int Model::body_index(const std::string& body_name) const {
    if (body_name == "ground") return kGround;
    for (int k = 0; k < body_count(); ++k)
        if (bodies[k].name == body_name) return k;
    return -2;
}

std::string Model::body_name(int index) const {
    return index == kGround ? std::string("ground") : bodies.at(index).name;
}

void Model::add_flexible_body(FlexibleBodyInstance body) {
    body.size = body.body->coordinates();
    body.offset = body_count() * coordinates_per_body(dimension) + flexible_coordinates_;
    body.v_offset = body_count() * velocities_per_body(dimension) + flexible_coordinates_;
    flexible_coordinates_ += body.size;
    flexible_bodies.push_back(std::move(body));
}

int Model::flexible_body_index(const std::string& name) const {
    for (size_t k = 0; k < flexible_bodies.size(); ++k)
        if (flexible_bodies[k].name == name) return static_cast<int>(k);
    return -1;
}

State Model::initial_state() const {
    State s;
    s.t = 0.0;
    s.q.setZero(nq());
    s.v.setZero(nv());
    for (int k = 0; k < body_count(); ++k) {
        const Body& b = bodies[k];
        if (dimension == Dimension::Planar) {
            s.q.segment<3>(q_offset(k)) << b.position.x(), b.position.y(), b.angle;
            s.v.segment<3>(v_offset(k)) << b.velocity.x(), b.velocity.y(), b.angular_velocity.z();
        } else {
            s.q.segment<3>(q_offset(k)) = b.position;
            s.q.segment<4>(q_offset(k) + 3) = b.euler_parameters.normalized();
            s.v.segment<3>(v_offset(k)) = b.velocity;
            // the scene gives the angular velocity in world axes; v holds body axes
            const Mat3 A = rotation_from_euler_parameters(b.euler_parameters.normalized());
            s.v.segment<3>(v_offset(k) + 3) = A.transpose() * b.angular_velocity;
        }
    }
    for (const FlexibleBodyInstance& f : flexible_bodies) s.q.segment(f.offset, f.size) = f.body->initial_coordinates();
    return s;
}

void advance_positions(const Model& model, Eigen::VectorXd& q, const Eigen::VectorXd& dv) {
    if (model.dimension == Dimension::Planar) {
        q += dv;
        return;
    }
    for (int k = 0; k < model.body_count(); ++k) {
        const int iq = model.q_offset(k), iv = model.v_offset(k);
        q.segment<3>(iq) += dv.segment<3>(iv);
        q.segment<4>(iq + 3) = rotate_euler_parameters_body(q.segment<4>(iq + 3), dv.segment<3>(iv + 3));
    }
    // flexible bodies: v = qdot (sdk body.hpp), their coordinates follow the rigid ones' in both
    const int flexible = model.flexible_coordinates();
    q.tail(flexible) += dv.tail(flexible);
}

Eigen::VectorXd coordinate_rates(const Model& model, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
    if (model.dimension == Dimension::Planar) return v;
    Eigen::VectorXd qdot(model.nq());
    for (int k = 0; k < model.body_count(); ++k) {
        const int iq = model.q_offset(k), iv = model.v_offset(k);
        qdot.segment<3>(iq) = v.segment<3>(iv);
        qdot.segment<4>(iq + 3) = 0.5 * euler_Gbar(q.segment<4>(iq + 3)).transpose() * v.segment<3>(iv + 3);
    }
    const int flexible = model.flexible_coordinates();
    qdot.tail(flexible) = v.tail(flexible);
    return qdot;
}

void normalize_euler_parameters(const Model& model, Eigen::VectorXd& q) {
    if (model.dimension == Dimension::Planar) return;
    for (int k = 0; k < model.body_count(); ++k) q.segment<4>(model.q_offset(k) + 3).normalize();
}

void require_holonomic(const Model& model, const std::string& analysis, const std::string& instead) {
    for (const JointInstance& j : model.joints)
        if (j.joint->velocity_rows() > 0)
            throw InputError(j.where, "joint '" + j.name + "' (type " + j.type + ") has " +
                                          std::to_string(j.joint->velocity_rows()) +
                                          " velocity-level (nonholonomic) constraint row(s), which " + analysis +
                                          " does not handle (it works on the position constraints only); " + instead);
}

}  // namespace mbd
