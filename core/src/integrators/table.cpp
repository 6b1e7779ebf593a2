// The integrators, each described once (integrator.hpp IntegratorDescription): the command
// line, Python, the messages and the automatic choice read these rows.
#include "table.hpp"

namespace mbd::integrators {

// Each integrator's file defines its make function.
std::unique_ptr<Integrator> make_euler(const IntegratorSettings&);
std::unique_ptr<Integrator> make_rk4(const IntegratorSettings&);
std::unique_ptr<Integrator> make_dopri5(const IntegratorSettings&);
std::unique_ptr<Integrator> make_dop853(const IntegratorSettings&);
std::unique_ptr<Integrator> make_generalized_alpha(const IntegratorSettings&);
std::unique_ptr<Integrator> make_cvode(const IntegratorSettings&);
std::unique_ptr<Integrator> make_ssp_rk3(const IntegratorSettings&);

const std::vector<IntegratorRow>& integrator_table() {
    using A = IntegratorDescription::Automatic;
    // name, order, adaptive, locates events, needs index 3, stiff, automatic choice, summary
    static const std::vector<IntegratorRow> table = {
        {{"euler", 1, false, false, false, false, A::Never, "explicit Euler, fixed step (for checks)"}, &make_euler},
        {{"rk4", 4, false, false, false, false, A::Never, "classical Runge-Kutta, fixed step"}, &make_rk4},
        {{"ssp_rk3", 3, false, false, false, false, A::Never, "Shu-Osher strong-stability-preserving RK3, fixed step"},
         &make_ssp_rk3},
        {{"dopri5", 5, true, true, false, false, A::Never, "Dormand-Prince 5(4), adaptive, dense output"},
         &make_dopri5},
        {{"dop853", 8, true, true, false, false, A::NotStiff, "Dormand-Prince 8(5,3), adaptive, dense output"},
         &make_dop853},
        {{"generalized_alpha", 2, false, false, true, true, A::Never,
          "generalized-alpha on the index-3 equations, implicit, fixed step"},
         &make_generalized_alpha},
        {{"cvode", 5, true, true, false, true, A::Stiff, "SUNDIALS CVODE BDF orders 1-5, implicit, adaptive"},
         &make_cvode},
    };
    return table;
}

}  // namespace mbd::integrators
