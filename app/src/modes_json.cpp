// The JSON report of a modes study (modes_json.hpp).
#include <mbd/app/modes_json.hpp>

namespace mbd {

namespace {

Json complex_array(const Eigen::VectorXcd& x) {
    Json out = Json::array();
    for (Eigen::Index i = 0; i < x.size(); ++i) out.push_back(Json::array({x[i].real(), x[i].imag()}));
    return out;
}

Json matrix_json(const Eigen::MatrixXd& M) {
    Json out = Json::array();
    for (Eigen::Index i = 0; i < M.rows(); ++i) {
        // a matrix without columns (B of a scene without actuators) has no row to take a block of
        if (M.cols() == 0)
            out.push_back(Json::array());
        else
            out.push_back(json_array(M.row(i).transpose()));
    }
    return out;
}

}  // namespace

const char* mode_kind(const Mode& m) { return m.oscillatory ? "oscillatory" : m.free_velocity ? "free_velocity" : "real"; }

std::vector<std::string> state_names(const LinearModel& linear) {
    std::vector<std::string> out;
    for (const std::string& c : linear.coordinates) out.push_back(c);
    for (const std::string& c : linear.velocity_coordinates) out.push_back(c + "_rate");
    return out;
}

Json modes_json(const std::string& about, const LinearModel& linear, const ModeAnalysis& analysis) {
    Json doc;
    doc["about"] = about;
    doc["residual"] = linear.residual;
    doc["coordinates"] = linear.coordinates;
    doc["velocity_coordinates"] = linear.velocity_coordinates;
    doc["joint_coordinates"] = linear.joint_coordinates;
    doc["states"] = state_names(linear);
    doc["inputs"] = linear.inputs;
    Json modes = Json::array();
    for (const Mode& m : analysis.modes) {
        Json j;
        j["kind"] = mode_kind(m);
        j["eigenvalue"] = Json::array({m.eigenvalue.real(), m.eigenvalue.imag()});
        j["natural_frequency"] = m.natural_frequency;
        j["damped_frequency"] = m.damped_frequency;
        j["damping_ratio"] = m.damping_ratio;
        j["shape"] = complex_array(m.shape);
        j["joint_shape"] = complex_array(m.joint_shape);
        modes.push_back(j);
    }
    doc["modes"] = modes;
    Json ignorable = Json::array();
    for (const IgnorableDirection& d : analysis.ignorable) ignorable.push_back(describe(d, linear.coordinates));
    doc["ignorable"] = ignorable;
    doc["A"] = matrix_json(linear.A);
    doc["B"] = matrix_json(linear.B);
    return doc;
}

}  // namespace mbd
