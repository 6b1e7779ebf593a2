// The cross-section profiles of the wheel_rail joint (book Sec. 8.6): a function f(x) of one
// lateral coordinate with its first two derivatives (the joint's acceleration terms use the
// curvature, so every profile is C2):
//   wheel: the rolling radius r(s) against the lateral coordinate s along the axle,
//          cone   — r = r0 - s tan(gamma) (a conical tread; gamma = 0: a cylinder), |s| <= width / 2,
//          spline — the natural cubic spline through points [s_k, r_k];
//   rail:  the head's height h(y) against the lateral coordinate y across the track,
//          flat   — h = 0,
//          arc    — a circular crown of radius R, its top at y = 0: h = sqrt(R^2 - y^2) - R,
//          spline — the natural cubic spline through points [y_k, h_k].
// A natural spline has zero curvature at its end points, so beyond them it goes on as the
// straight line of its end slope (still C2).
#pragma once

#include <mbd/sdk/params.hpp>

#include <cmath>

#include <memory>
#include <string>

namespace mbd::wheel_rail {

struct CurveValue {
    double f = 0.0, f1 = 0.0, f2 = 0.0;  // f, df/dx, d2f/dx2
};

class ProfileCurve {
public:
    virtual ~ProfileCurve() = default;
    virtual CurveValue at(double x) const = 0;
    // true when f'' = 0 everywhere (a cone, a flat head): such a pair touches along a line
    virtual bool straight() const { return false; }
    // a lateral coordinate inside the profile's range (the starting guess of the contact search)
    virtual double clamp(double x) const { return x; }
    // where f' = slope (the point whose normal has a given tilt), near `guess`; a straight
    // profile has one slope everywhere and returns the guess
    virtual double where_slope(double /*slope*/, double guess) const { return guess; }
    // The lateral range the profile describes (a contact outside it is off the tread or the
    // head; a spline's straight continuation beyond its points serves only the contact search):
    // a flat head is unbounded, a cone its width, an arc crown spans (-R, R), a spline its points.
    struct Range {
        double lo, hi;
        bool contains(double x) const { return x >= lo && x <= hi; }
        double outside_by(double x) const { return x < lo ? lo - x : x - hi; }
    };
    virtual Range domain() const { return {-HUGE_VAL, HUGE_VAL}; }
};

// Reads `wheel:` ({type: cone | spline, ...}) or `rail:` ({type: flat | arc | spline, ...}) of a
// wheel_rail joint; throws InputError naming the joint (`who`) and the key on bad input.
std::unique_ptr<const ProfileCurve> read_wheel_profile(const Params& joint, const std::string& who);
std::unique_ptr<const ProfileCurve> read_rail_profile(const Params& joint, const std::string& who);

}  // namespace mbd::wheel_rail
