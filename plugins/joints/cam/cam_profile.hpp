// A planar cam profile in polar form (book Sec. 3.4, Eqs. 3.96b-3.97): the radius d(phi) of
// the profile point at polar angle phi about the profile frame's origin, 2 pi periodic, so
//   rho(phi) = d(phi) [cos phi, sin phi]                                   (profile frame)
//   rho'     = d' [cos, sin] + d [-sin, cos]                               (tangent, Eq. 3.102)
//   rho''    = (d'' - d) [cos, sin] + 2 d' [-sin, cos].
// The joint needs d, d' and d'' (its acceleration terms use the curvature), so every profile
// is at least C2:
//   eccentric: a circle of radius R whose centre is at distance e < R on the frame's x axis,
//              d = e cos phi + sqrt(R^2 - e^2 sin^2 phi) (the ray from the origin meets it once);
//   harmonic : d = a0 + sum_k (a_k cos k phi + b_k sin k phi);
//   spline   : the periodic cubic spline through radii d_k at phi_k = 2 pi k / n (C2, its
//              second derivatives from the cyclic tridiagonal system of the periodic end
//              conditions).
#pragma once

#include <mbd/sdk/params.hpp>
#include <mbd/sdk/rotation.hpp>

#include <memory>
#include <string>
#include <vector>

namespace mbd::cam {

struct RadiusValue {
    double d = 0.0, d1 = 0.0, d2 = 0.0;  // d, dd/dphi, d2d/dphi2
};

// The profile point and its first two derivatives with respect to phi, profile frame.
struct ProfilePoint {
    Vec2 rho, rho1, rho2;
};

class Profile {
public:
    virtual ~Profile() = default;
    virtual RadiusValue radius(double phi) const = 0;
    ProfilePoint point(double phi) const;
};

// Reads the `profile:` map of a cam joint ({type: eccentric | harmonic | spline, ...});
// throws InputError naming the key on bad input (`who`: "cam 'NAME'").
std::unique_ptr<const Profile> read_profile(const Params& params, const std::string& who);

// The periodic cubic spline alone (for tests and other profiles): radii at phi_k = 2 pi k / n.
std::unique_ptr<const Profile> periodic_spline(const std::vector<double>& radii);

}  // namespace mbd::cam
