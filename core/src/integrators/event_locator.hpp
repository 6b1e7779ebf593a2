// Event location for the one-step integrators (dopri5): after an accepted step, the
// problem's event functions are compared with the side each was on; on a change, the
// earliest root is located on the step's continuous extension (the Illinois variant of
// regula falsi, to a few units of round-off in time) and the integrator re-takes the
// step to end exactly there, so no step straddles an event. Then the problem acts on the
// events (OdeProblem::handle_events) and the integrator restarts from the new state.
//
// A sign change is a function leaving its side: g < 0 on the open side (+1), g > 0 on the
// closed side (-1); a value of exactly 0 leaves neither. Two roots of one function inside
// one step (a gap that closes and opens again between two step ends) are not seen; the
// error control keeps steps short against the motion, so this needs a touch shorter than
// a step.
#pragma once

#include <mbd/integrator.hpp>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace mbd::integrators {

// Events one after another at (nearly) one time: a contact that chatters without end would
// never let time advance. check() throws DynamicsError after more than 100 in a row.
class EventPileUpGuard {
public:
    void reset(double t0) {
        last_time_ = t0;
        repeats_ = 0;
    }
    void check(double t, const OdeProblem& problem, int event);

private:
    double last_time_ = 0.0;
    int repeats_ = 0;
};

class EventLocator {
public:
    // Sizes the work and takes each event's side at (t0, y0): open (+1) unless g < 0.
    void start(OdeProblem& problem, double t0, const Eigen::VectorXd& y0);
    bool active() const { return !side_.empty(); }
    // True when some event function left its side at the step end (t, y).
    bool left_side(OdeProblem& problem, double t, const Eigen::VectorXd& y);
    // The earliest root in (0, 1] of the step fraction theta on the interpolant
    // `at(theta, y_theta)` of the step from t of size h, for the functions left_side found;
    // it returns the first fraction found past the root (the function has changed sign
    // there) and records which events cross at it.
    template <class Interpolant>
    double locate(OdeProblem& problem, double t, double h, Interpolant&& at);
    // At the event time t: flips the crossing events' sides, lets the problem act and
    // counts the events; true when the problem changed y. Throws DynamicsError when
    // events pile up at one time (a contact that chatters without end).
    bool handle(OdeProblem& problem, double t, Eigen::VectorXd& y, IntegratorStats& stats);

private:
    bool crosses(int event, double g) const { return side_[event] > 0 ? g < 0.0 : g > 0.0; }

    std::vector<int> side_, crossed_, candidates_;
    Eigen::VectorXd g_, y_theta_;
    EventPileUpGuard pile_up_;
};

template <class Interpolant>
double EventLocator::locate(OdeProblem& problem, double t, double h, Interpolant&& at) {
    const double tol = 8.0 * 2.220446049250313e-16 * std::max(std::abs(t), std::abs(h)) / std::abs(h);
    double best = 1.0;
    crossed_.clear();
    for (int event : candidates_) {
        // this function's value times its side: > 0 before the root, <= 0 past it
        auto value = [&](double theta) {
            at(theta, y_theta_);
            problem.event_values(t + theta * h, y_theta_, g_);
            return side_[event] > 0 ? g_[event] : -g_[event];
        };
        double b = best, fb = value(b);
        if (!(fb < 0.0)) continue;  // its root lies after an earlier event's: found in a later step
        double a = 0.0, fa = std::max(value(0.0), 1e-300);  // at the step's start it is on its side
        int moved = 0;  // the end moved last (+1 b, -1 a); Illinois halves the value kept twice
        for (int iteration = 0; iteration < 200 && b - a > tol; ++iteration) {
            double c = b - fb * (b - a) / (fb - fa);
            if (!(c > a && c < b)) c = 0.5 * (a + b);
            const double fc = value(c);
            if (fc < 0.0) {
                b = c;
                fb = fc;
                if (moved > 0) fa *= 0.5;
                moved = +1;
            } else {
                a = c;
                fa = fc;
                if (moved < 0) fb *= 0.5;
                moved = -1;
            }
        }
        if (b < best - tol) crossed_.clear();
        best = std::min(best, b);
        crossed_.push_back(event);
    }
    return best;
}

}  // namespace mbd::integrators
