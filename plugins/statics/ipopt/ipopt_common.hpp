// Small Ipopt helpers shared by the statics and inverse-dynamics solvers.
#pragma once

#include <IpIpoptApplication.hpp>

#include <mutex>
#include <string>

namespace mbd::ipopt_plugin {

// Ipopt's linear solver, Debian's sequential MUMPS, keeps global state (Fortran module
// variables): two solves at once in one process corrupt each other (a Fortran runtime error
// or a crash, met with Python threads running statics). Every use of Ipopt, from creating the
// application to the end of its last solve, holds this lock; the rest of a statics or
// inverse-dynamics run goes on in parallel.
inline std::mutex& ipopt_lock() {
    static std::mutex lock;
    return lock;
}

inline std::string status_name(Ipopt::ApplicationReturnStatus s) {
    switch (s) {
        case Ipopt::Solve_Succeeded: return "Solve_Succeeded";
        case Ipopt::Solved_To_Acceptable_Level: return "Solved_To_Acceptable_Level";
        case Ipopt::Infeasible_Problem_Detected: return "Infeasible_Problem_Detected";
        case Ipopt::Search_Direction_Becomes_Too_Small: return "Search_Direction_Becomes_Too_Small";
        case Ipopt::Diverging_Iterates: return "Diverging_Iterates";
        case Ipopt::User_Requested_Stop: return "User_Requested_Stop";
        case Ipopt::Feasible_Point_Found: return "Feasible_Point_Found";
        case Ipopt::Maximum_Iterations_Exceeded: return "Maximum_Iterations_Exceeded";
        case Ipopt::Restoration_Failed: return "Restoration_Failed";
        case Ipopt::Error_In_Step_Computation: return "Error_In_Step_Computation";
        case Ipopt::Maximum_CpuTime_Exceeded: return "Maximum_CpuTime_Exceeded";
        case Ipopt::Not_Enough_Degrees_Of_Freedom: return "Not_Enough_Degrees_Of_Freedom";
        case Ipopt::Invalid_Problem_Definition: return "Invalid_Problem_Definition";
        case Ipopt::Invalid_Option: return "Invalid_Option";
        case Ipopt::Invalid_Number_Detected: return "Invalid_Number_Detected";
        case Ipopt::Unrecoverable_Exception: return "Unrecoverable_Exception";
        case Ipopt::NonIpopt_Exception_Thrown: return "NonIpopt_Exception_Thrown";
        case Ipopt::Insufficient_Memory: return "Insufficient_Memory";
        case Ipopt::Internal_Error: return "Internal_Error";
        default: return "Unknown_Status";
    }
}

inline bool succeeded(Ipopt::ApplicationReturnStatus s) {
    return s == Ipopt::Solve_Succeeded || s == Ipopt::Solved_To_Acceptable_Level;
}

// Ipopt stopped at a solution: succeeded, or its step became too small to change x
// (at the precision floor of the gradient, e.g. stiff springs: dual infeasibility
// 8e-10 against |Q| ~ 1e4 in the 1000-body chain). The equilibrium residual is still
// checked independently (max |C|, |Q - J^T lambda|, limits <= 1e-6 (1 + max |Q|)).
inline bool finished(Ipopt::ApplicationReturnStatus s) {
    return succeeded(s) || s == Ipopt::Search_Direction_Becomes_Too_Small;
}

}  // namespace mbd::ipopt_plugin
