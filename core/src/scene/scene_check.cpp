// The checks of `mbd check` (scene_check.hpp).
#include <mbd/scene_check.hpp>

#include <mbd/model_system.hpp>
#include <mbd/kit/topology.hpp>

#include <Eigen/Dense>

#include <algorithm>

namespace mbd {

SceneCheck check_scene(const Model& model, double rank_tolerance) {
    SceneCheck check;
    const ConstraintSystem system(model, true);
    Data data(model);
    check.assembled = model.initial_state();
    check.assembled.t = 0.0;
    check.assembly = assemble_positions(system, data, check.assembled);
    check.mobility = analyse_mobility(model, check.assembled, rank_tolerance);
    check.full_rank = check.mobility.rank;
    if (!model.drivers.empty()) {
        ConstraintValues values;
        system.evaluate(check.assembled, data, values);
        Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr{Eigen::MatrixXd(values.J)};
        qr.setThreshold(rank_tolerance);
        check.full_rank = static_cast<int>(qr.rank());
        check.dependent_driver_rows =
            std::max(0, check.mobility.rank + static_cast<int>(model.drivers.size()) - check.full_rank);
    }
    check.free_dof = model.nv() - check.full_rank;
    check.kinematically_driven = !model.drivers.empty() && check.free_dof == 0;
    const ModelSystem topology_system(model);
    check.embedding.path = "recursive";
    if (!recursive_embedding_possible(topology_system, &check.embedding.reason)) {
        std::string closure_reason;
        const bool closure = closure_embedding_possible(topology_system, &closure_reason);
        check.embedding.path = closure ? "closure" : "dense";
        if (closure) check.embedding.reason = closure_reason;
    }
    return check;
}

}  // namespace mbd
