#include "simulation/lift_off.hpp"

#include <mbd/sdk/text.hpp>

namespace mbd {

LiftOffWatch::LiftOffWatch(const System& system) {
    for (int j = 0; j < system.joint_count(); ++j) {
        const JointInfo& info = system.joint(j);
        for (int r = 0; r < info.rows; ++r) {
            const int sign = info.joint->compression_sign(r);
            if (sign != 0) rows_.push_back({info.first_row + r, sign > 0 ? 1 : -1, info.name, info.joint->row_name(r)});
        }
    }
}

void LiftOffWatch::check(double t, const Eigen::VectorXd& lambda, const MessageLog& log,
                         std::vector<LiftOffRecord>& records) {
    for (Row& row : rows_) {
        const double force = row.sign * lambda[row.row];  // > 0: compression
        if (row.seen && row.force > 0.0 && force <= 0.0) {
            const double zero = force == row.force ? t : row.t + (t - row.t) * row.force / (row.force - force);
            records.push_back({zero, row.joint, row.name});
            log("warning: joint '" + row.joint + "' (" + row.name + "): the contact force reaches zero at t = " +
                format_time(zero) +
                " s, where the bodies would separate (the joint keeps them in contact; a stronger spring "
                "or a lower speed keeps the contact force compressive)");
        }
        row.seen = true;
        row.t = t;
        row.force = force;
    }
}

}  // namespace mbd
