// Two spheres (planar: circles), one on each body, with the compliant normal law and friction
// of mbd/sdk/contact.hpp.
//
// Keys: `points: [centre i, centre j]` (each in its body's own frame; default the mass
// centres), `radii: [r_i, r_j]` (> 0), and the law's keys (contact.hpp).
// g = |C_j - C_i| - r_i - r_j; the normal is along the line of centres and the contact point
// the middle of the overlap. Coincident centres (an overlap of r_i + r_j) give no normal: the
// element then applies no force rather than stopping the run.
#pragma once

#include "contact_frames.hpp"

#include <mbd/sdk/contact.hpp>

#include <algorithm>
#include <array>
#include <string>

namespace mbd::contact {

class SphereContact final : public ContactForce<SphereContact> {
public:
    SphereContact(const ForceSpec& spec, Dimension accepted, const std::string& other)
        : ContactForce(spec, accepted, other), centres_(contact_points(spec, "centre i, centre j")) {
        if (!spec.params.has("radii")) force_support::fail(spec, "missing key 'radii' ([r_i, r_j], the radii, m)");
        const Eigen::VectorXd r = force_support::number_list(spec, "radii", 2, false);
        for (int k = 0; k < 2; ++k) {
            if (!(r[k] > 0.0))
                force_support::fail(spec, "'radii' must be positive (the radius of body '" + spec.bodies[k].name +
                                              "''s sphere, m), got " + std::to_string(r[k]),
                                    &spec.params.at("radii").items[k]);
            radii_[k] = r[k];
        }
        refuse_deep_start(spec, std::min(radii_[0], radii_[1]),
                          spec.dimension == Dimension::Planar ? "the smaller circle's radius" : "the smaller sphere's radius");
    }

    template <class S>
    ContactGeometry<S, 2> geometry(const force_support::PlanarStates<S>& s) const {
        return sphere_on_sphere<S, 2>(s[0].point(centres_[0].head<2>()), radii_[0], s[1].point(centres_[1].head<2>()),
                                      radii_[1]);
    }
    template <class S>
    ContactGeometry<S, 3> geometry(const force_support::SpatialStates<S>& s) const {
        return sphere_on_sphere<S, 3>(s[0].point(centres_[0]), radii_[0], s[1].point(centres_[1]), radii_[1]);
    }

private:
    std::array<Vec3, 2> centres_;
    double radii_[2] = {0.0, 0.0};
};

}  // namespace mbd::contact
