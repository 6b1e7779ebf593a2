// The reference state, linearisation and modes of `mbd modes` and Model.modes() (modes_study.hpp).
#include <mbd/modes_study.hpp>

#include <mbd/model.hpp>
#include <mbd/registry.hpp>
#include <mbd/model_system.hpp>
#include <mbd/sdk/params.hpp>
#include <mbd/statics_analysis.hpp>

namespace mbd {

ModesStudy study_modes(const Model& model, Registry& registry, const ModesStudyOptions& options) {
    if (options.about != "statics" && options.about != "initial")
        throw InputError("about", "expected 'statics' or 'initial', got '" + options.about + "'");
    require_linearisable(model);  // before the statics
    State reference = model.initial_state();
    {
        ModelSystem system(model);
        require_freedom(system, reference);  // a driven mechanism: named, before the statics
    }
    ModesStudy study;
    if (options.about == "statics") {
        StaticsOptions statics;
        statics.max_iterations = options.statics_iterations;
        const StaticsReport report = run_statics(model, registry, statics, options.solver);
        if (!report.result.converged) {
            study.statics_converged = false;
            study.statics_message = report.result.message;
            return study;
        }
        reference = report.result.state;
        reference.v = Eigen::VectorXd::Zero(model.nv());
    }
    ModelSystem system(model);
    LinearisationOptions linearisation;
    linearisation.residual_tolerance = options.residual_tolerance;
    study.linear = linearise(system, reference, scene_actuators(model), linearisation);
    study.analysis = modes_of(study.linear);
    return study;
}

}  // namespace mbd
