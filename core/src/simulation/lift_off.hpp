// Watches the contact rows of a forward-dynamics run that can only push in reality
// (Joint::compression_sign, sdk joint.hpp: a cam and its spring-loaded follower). The rows are
// bilateral, so the run holds the bodies together whatever the sign of the contact force; at
// every output sample the watch reads the rows' multipliers and, where one leaves its
// compression sign, reports the time at which the contact force passed through zero (linear
// interpolation between the two samples around the change): there the bodies would separate.
#pragma once

#include <mbd/kit/message_log.hpp>
#include <mbd/kit/system.hpp>
#include <mbd/simulation.hpp>

#include <Eigen/Core>

#include <vector>

namespace mbd {

class LiftOffWatch {
public:
    explicit LiftOffWatch(const System& system);
    bool active() const { return !rows_.empty(); }
    // One output sample with the multipliers of every row (System layout); appends a record
    // and writes a warning line to `log` for each contact force that has just passed zero.
    void check(double t, const Eigen::VectorXd& lambda, const MessageLog& log, std::vector<LiftOffRecord>& records);

private:
    struct Row {
        int row = 0;          // in the constraint vector
        int sign = 0;         // its compression sign
        std::string joint, name;
        bool seen = false;
        double t = 0.0, force = 0.0;  // the previous sample: time and sign * multiplier
    };
    std::vector<Row> rows_;
};

}  // namespace mbd
