// A surface contact of one row (book Sec. 8.6, the surface parameters solved inside the joint):
// the normal gap, whose multiplier is the normal force, in compression while negative
// (Joint::compression_sign: a forward run warns where the bodies would separate).
#pragma once

#include <mbd/sdk/joint.hpp>

#include <string>

namespace mbd {

class ContactJoint : public Joint {
public:
    int rows() const override { return 1; }
    std::string row_name(int /*row*/) const override { return "contact"; }
    int compression_sign(int /*row*/) const override { return -1; }

protected:
    // Zero the output before the row is written.
    static void clear(ConstraintEval& out) {
        out.C.setZero();
        out.J.setZero();
        out.C_t.setZero();
        out.gamma.setZero();
    }
};

}  // namespace mbd
