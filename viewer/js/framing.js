// The default camera: it frames the mechanism, not the whole path of one that travels. A
// mechanism whose mass centres' mean travels farther than twice its own size (a vehicle) is
// framed at its size and followed (the camera and its orbit target move with that mean);
// any other is framed with every place it reaches in view.
import * as THREE from 'three';

export const kFollowTravel = 2;  // travel over size above which following is the default

// The box around every body shape as drawn now (instances of bodies, not ground or springs).
export function bodiesBox(instanced, out) {
  const m = new THREE.Matrix4(), box = new THREE.Box3();
  out.makeEmpty();
  instanced.forEach(({ mesh, items }) => items.forEach((item, i) => {
    if (item.body < 0) return;
    mesh.getMatrixAt(i, m);
    out.union(box.copy(mesh.geometry.boundingBox).applyMatrix4(m));
  }));
  return out;
}

export const meanPosition = (groups, out) => {
  out.set(0, 0, 0);
  groups.forEach((g) => out.add(g.position));
  return out.multiplyScalar(1 / Math.max(groups.length, 1));
};

// What to frame. `start`: the bodies' box at the first frame; `massCentres`: the box of every
// mass centre over the motion; `meanPath`: the box of the mean mass centre over the motion.
export function chooseFraming(start, massCentres, meanPath) {
  const size = start.getSize(new THREE.Vector3()).length();
  const travel = meanPath.getSize(new THREE.Vector3()).length();
  const follow = travel > kFollowTravel * size;
  const box = start.clone();
  if (!follow) {
    // every mass centre's reach, padded by how far the shapes stand out of their mass centres
    const startCentres = massCentres.startBox;
    const pad = Math.max(0, ...start.min.clone().sub(startCentres.min).toArray().map(Math.abs),
                         ...start.max.clone().sub(startCentres.max).toArray().map(Math.abs));
    box.union(massCentres.box.clone().expandByScalar(pad));
  }
  box.expandByScalar(0.08 * Math.max(box.getSize(new THREE.Vector3()).length(), 1e-9));
  return { follow, box, size, travel };
}

// Places the camera looking at `box` along `viewDir` (unit, from the target to the camera)
// so that its bounding sphere fits the vertical field of view.
export function frameBox(camera, controls, box, viewDir) {
  const centre = box.getCenter(new THREE.Vector3());
  const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1e-9);
  const halfFov = THREE.MathUtils.degToRad(camera.fov / 2);
  camera.position.copy(centre).addScaledVector(viewDir, (radius / Math.sin(halfFov)) * 1.02);
  camera.near = radius / 100; camera.far = radius * 200;
  camera.updateProjectionMatrix();
  controls.target.copy(centre);
  controls.update();
  return radius;
}
