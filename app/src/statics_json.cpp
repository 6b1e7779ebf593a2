// The JSON report of a static equilibrium (statics_json.hpp).
#include <mbd/app/statics_json.hpp>

#include <cmath>

namespace mbd {

namespace {

Json load_json(const JointLoad& l, bool planar) {
    if (planar) return {{"fx", l.force.x()}, {"fy", l.force.y()}, {"tz", l.torque.z()}};
    return {{"fx", l.force.x()},  {"fy", l.force.y()},  {"fz", l.force.z()},
            {"tx", l.torque.x()}, {"ty", l.torque.y()}, {"tz", l.torque.z()}};
}

}  // namespace

Json statics_json(const Model& model, const StaticsReport& rep, const std::vector<JointLimit>& limits) {
    const StaticsResult& r = rep.result;
    const bool planar = model.dimension == Dimension::Planar;
    Json o;
    o["converged"] = r.converged;
    o["status"] = r.status;
    o["iterations"] = r.iterations;
    o["residual"] = r.residual;
    o["objective"] = r.objective;
    o["stability"] = r.stability;
    if (!r.message.empty()) o["message"] = r.message;
    o["tangent_eigenvalues"] = json_array(r.tangent_eigenvalues);
    Json bodies = Json::object();
    for (int b = 0; b < model.body_count(); ++b) {
        Json& body = bodies[model.bodies[b].name];
        if (planar) {
            body = {{"x", r.state.q[3 * b]}, {"y", r.state.q[3 * b + 1]}, {"angle", r.state.q[3 * b + 2]}};
        } else {
            const char* keys[] = {"x", "y", "z", "e0", "e1", "e2", "e3"};
            for (int i = 0; i < 7; ++i) body[keys[i]] = r.state.q[7 * b + i];
        }
    }
    o["bodies"] = std::move(bodies);
    Json flexible = Json::object();  // each flexible body's node positions and coordinates at the equilibrium
    for (const FlexibleBodyInstance& f : model.flexible_bodies) {
        const Eigen::VectorXd q = r.state.q.segment(f.offset, f.size), v = Eigen::VectorXd::Zero(f.size);
        Json nodes = Json::array();
        for (int k = 0; k < f.body->node_count(); ++k) {
            const std::vector<double> xi = f.body->node_parameters(k);
            MaterialPoint p;
            f.body->point(q, v, xi.data(), p);
            nodes.push_back(planar ? Json::array({p.r.x(), p.r.y()}) : Json::array({p.r.x(), p.r.y(), p.r.z()}));
        }
        Json coordinates = Json::object();  // by the body's names (an ffrf_body's x, y, angle, mode1 ...)
        for (int k = 0; k < f.size; ++k) coordinates[f.body->coordinate_name(k)] = q[k];
        flexible[f.name] = {{"nodes", std::move(nodes)}, {"coordinates", std::move(coordinates)}};
    }
    if (!model.flexible_bodies.empty()) o["flexible_bodies"] = std::move(flexible);
    Json reactions = Json::object();
    for (const JointLoad& load : rep.reactions) reactions[load.name] = load_json(load, planar);
    o["reactions"] = std::move(reactions);
    Json coordinates = Json::object();
    for (size_t j = 0; j < rep.coordinates.size(); ++j) coordinates[model.joints[j].name] = rep.coordinates[j];
    o["coordinates"] = std::move(coordinates);
    Json drivers = Json::object();
    const int joint_rows = r.lambda.size() - static_cast<int>(model.drivers.size());
    for (size_t d = 0; d < model.drivers.size(); ++d) {
        const double multiplier = r.lambda.size() ? r.lambda[joint_rows + d] : NAN;
        Json driver = {{"multiplier", multiplier}, {"effort", -multiplier}};
        if (d < rep.driver_efforts.size()) driver["load"] = load_json(rep.driver_efforts[d], planar);
        drivers[model.drivers[d].name] = std::move(driver);
    }
    o["drivers"] = std::move(drivers);
    Json limit_out = Json::object();
    for (size_t k = 0; k < limits.size(); ++k) {
        const bool active = k < r.limit_active.size() && r.limit_active[k];
        const double nu = static_cast<Eigen::Index>(k) < r.limit_multipliers.size() ? r.limit_multipliers[k] : 0.0;
        limit_out[model.joints[limits[k].joint].name] = {
            {"lo", limits[k].lo}, {"hi", limits[k].hi}, {"active", active}, {"multiplier", nu}, {"effort", -nu}};
    }
    o["limits"] = std::move(limit_out);
    // redundant rows: the reactions above are the minimum-norm ones (StaticIndeterminacy)
    const StaticIndeterminacy& in = rep.indeterminacy;
    o["reactions_determined"] = !in.any();
    Json redundant = Json::array();
    for (const RowOwner& row : in.redundant_rows) redundant.push_back(row.describe());
    o["redundant_rows"] = std::move(redundant);
    o["undetermined_reactions"] = {{"joints", in.undetermined_joints}, {"drivers", in.undetermined_drivers}};
    return o;
}

}  // namespace mbd
