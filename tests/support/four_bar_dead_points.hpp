// A crank-rocker four-bar (book Table 3.2 links: ground 0.4, crank 0.2, coupler 0.4, rocker
// 0.5) in free motion without gravity: the crank turns round and the rocker passes its dead
// points (crank and coupler collinear), where the rocker angle cannot be an independent
// coordinate. Shared by the embedding and the sparse-partition tests; each adds its
// `formulation:` line.
#pragma once

#include <string>

namespace mbd::test {

inline std::string four_bar_dead_points(const std::string& formulation_line) {
    return std::string(R"(
name: four-bar-dead-points
dimension: planar
gravity: [0, 0]
bodies:
  - {name: crank, mass: 1, inertia: 0.0033333333333333335, position: [-3.6732051e-07, 0.09999999999932538], angle: 1.5708, angular_velocity: 5.0}
  - {name: coupler, mass: 1, inertia: 0.013333333333333334, position: [0.14010956179022666, 0.3427203728749434], angle: 0.794626308141491}
  - {name: rocker, mass: 1, inertia: 0.020833333333333332, position: [0.340109929110737, 0.242720372875618], angle: 4.954301901756992}
joints:
  - {name: O, type: revolute, bodies: [ground, crank], point: [0, 0]}
  - {name: A, type: revolute, bodies: [crank, coupler], point: [-7.3464102e-07, 0.1999999999986508]}
  - {name: B, type: revolute, bodies: [coupler, rocker], point: [0.280219858221474, 0.485440745751236]}
  - {name: C, type: revolute, bodies: [rocker, ground], point: [0.4, 0]}
)") + formulation_line + "\n";
}

}  // namespace mbd::test
