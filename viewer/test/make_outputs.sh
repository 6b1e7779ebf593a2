#!/usr/bin/env bash
# Simulates the scenes the viewer tests open and writes their CSV, .glb and .html into OUT.
# Usage: make_outputs.sh MBD SOURCE_DIR OUT
set -euo pipefail
mbd=$1 src=$2 out=$3
mkdir -p "$out"
run() {  # name scene t_end output_step
  "$mbd" simulate "$src/$2" --t-end "$3" --output-step "$4" --tol 1e-8 -q --diagnostics \
    --output "$out/$1.csv" --animation "$out/$1.html"
  "$mbd" animate "$src/$2" "$out/$1.csv" -o "$out/$1.glb" > /dev/null
}
# 3001 rows: more than twice the plot intervals, so the page holds its non-pose columns as envelopes
run four-bar scenes/four-bar.yaml 0.3 0.0001
run gyroscope scenes/bench/gyroscope.yaml 1.0 0.01
run chain-50 scenes/bench/chain-50.yaml 0.2 0.01
run visual-shapes scenes/examples/visual-shapes.yaml 1.0 0.01
# 15 m of riding at 5 m/s: a vehicle the camera follows
run whipple-bicycle scenes/reference/whipple-bicycle.yaml 3.0 0.01
"$mbd" statics "$src/scenes/statics/pendulum-torque.yaml" --animation "$out/statics.html" > /dev/null
"$mbd" statics "$src/scenes/statics/pendulum-torque.yaml" --animation "$out/statics.glb" > /dev/null
# a ball, a brick and a capsule falling onto a plane: the contacts the viewer draws (contacts.mjs)
"$mbd" simulate "$src/scenes/examples/force-collision-contact.yaml" --integrator dopri5 --tol 1e-8 --t-end 1 \
  --output-step 0.01 -q --output "$out/collision.csv" --contacts "$out/collision-contacts.csv" \
  --animation "$out/collision.html"
# an ANCF cable pendulum released horizontal: the tube the viewer draws through its nodes (flexible.mjs)
cat > "$out/cable-pendulum.yaml" <<'SCENE'
dimension: planar
gravity: [0, -9.81]
flexible_bodies:
  - {name: rope, type: ancf_cable, from: [0, 0], to: [1, 0], elements: 4, modulus: 1.0e4, area: 1.0, second_moment: 1.0e-3, density: 1.0}
joints:
  - {name: pin, type: revolute, bodies: [ground, {body: rope, node: 0}]}
SCENE
"$mbd" simulate "$out/cable-pendulum.yaml" --t-end 1 --output-step 0.01 --tol 1e-8 -q \
  --output "$out/cable-pendulum.csv" --animation "$out/cable-pendulum.html"
"$mbd" animate "$out/cable-pendulum.yaml" "$out/cable-pendulum.csv" -o "$out/cable-pendulum.glb" > /dev/null
# a spatial cable carrying a spinning rigid ball: a skinned tube beside a rigid body (validate_gltf.mjs)
cat > "$out/cable-ball.yaml" <<'SCENE'
dimension: spatial
gravity: [0, 0, -9.81]
flexible_bodies:
  - {name: rope, type: ancf_cable, from: [0, 0, 0], to: [0.8, 0.6, 0], elements: 3, modulus: 1.0e4, area: 1.0, second_moment: 1.0e-3, density: 1.0}
bodies:
  - {name: ball, mass: 0.5, inertia: [1.0e-3, 1.0e-3, 1.0e-3], position: [0.8, 0.6, 0], angular_velocity: [0, 0, 3]}
joints:
  - {name: pin, type: spherical, bodies: [ground, {body: rope, node: 0}], point: [0, 0, 0]}
  - {name: tip, type: spherical, bodies: [{body: rope, node: 3}, ball], point: [0.8, 0.6, 0]}
SCENE
"$mbd" simulate "$out/cable-ball.yaml" --t-end 0.4 --output-step 0.01 --tol 1e-8 -q \
  --output "$out/cable-ball.csv" --animation "$out/cable-ball.glb"
ls "$out"
