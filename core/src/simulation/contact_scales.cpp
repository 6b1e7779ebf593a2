// The scales a compliant contact holds (contact_scales.hpp).
#include <mbd/contact_scales.hpp>

#include <mbd/sdk/text.hpp>

#include <algorithm>
#include <cmath>

namespace mbd {

namespace {

// The mass a contact between bodies i and j carries: the body's against the ground, else the
// reduced mass (a body against its own kind, i == j: half its mass); 0 when neither has mass.
double carried_mass(const Model& model, int i, int j) {
    const double mi = i == kGround ? 0.0 : model.bodies[i].mass;
    const double mj = j == kGround ? 0.0 : model.bodies[j].mass;
    if (i == kGround) return mj;
    if (j == kGround) return mi;
    return mi + mj > 0.0 ? mi * mj / (mi + mj) : 0.0;
}

double largest_coordinate(const Model& model, const std::vector<int>& bodies) {
    double extent = 0.0;
    for (int b : bodies)
        if (b != kGround) extent = std::max(extent, model.bodies[b].position.cwiseAbs().maxCoeff());
    return extent;
}

}  // namespace

std::vector<ContactScale> contact_scales(const Model& model) {
    std::vector<ContactScale> scales;
    const double g = model.gravity.norm();
    for (const ForceInstance& f : model.forces) {
        if (!f.force) continue;
        for (const CompliantLaw& law : f.force->compliant_laws()) {
            const int count = static_cast<int>(f.bodies.size());
            if (law.body_i < 0 || law.body_i >= count || law.body_j < 0 || law.body_j >= count) continue;
            if (!(law.stiffness > 0.0) || !(law.exponent > 0.0)) continue;
            const int i = f.bodies[law.body_i], j = f.bodies[law.body_j];
            const double m = carried_mass(model, i, j);
            if (!(m > 0.0)) continue;
            const double k = law.stiffness, n = law.exponent;
            ContactScale s;
            s.element = f.name;
            s.mass = m;
            double smallest = 0.0, largest = 0.0;
            if (g > 0.0) {
                smallest = largest = std::pow(m * g / k, 1.0 / n);
                s.penetration_source = "at rest under its weight " + format_number(m * g, 3) + " N";
            }
            if (law.impact_velocity > 0.0) {
                const double v = law.impact_velocity;
                const double at_impact = std::pow((n + 1.0) * m * v * v / (2.0 * k), 1.0 / (n + 1.0));
                if (smallest == 0.0 || at_impact < smallest) {
                    smallest = at_impact;
                    s.penetration_source = "at its impact at " + format_number(v, 3) + " m/s";
                }
                largest = std::max(largest, at_impact);
            }
            if (!(smallest > 0.0)) continue;  // no gravity, no impact velocity: no scale before the run
            s.penetration = smallest;
            // the slope n k delta^(n-1) grows with delta for n > 1 and shrinks for n < 1
            const auto frequency = [&](double delta) { return std::sqrt(n * k * std::pow(delta, n - 1.0) / m); };
            s.frequency = std::max(frequency(smallest), frequency(largest));
            s.extent = largest_coordinate(model, {i, j});
            s.tolerance = s.penetration / (kPenetrationResolution * (1.0 + s.extent));
            scales.push_back(s);
        }
    }
    return scales;
}

}  // namespace mbd
