// How many pixels of the view each body covers: the scene drawn once more into an offscreen
// target with every instance in a flat colour that encodes its body (index + 1 in red and
// green; the ground, the grid and the springs black), read back and counted. Pixels under
// `hidden` (rectangles in CSS pixels of the canvas, e.g. the plot panel) do not count.
import * as THREE from 'three';

// one material and one target for every call: a new material would compile its shader again
const flat = new THREE.MeshBasicMaterial({ color: 0xffffff });
let target = null;

export function countBodyPixels(renderer, world, camera, instanced, hiddenParts, hidden, bodyCount) {
  const size = renderer.getDrawingBufferSize(new THREE.Vector2());
  if (!target || target.width !== size.x || target.height !== size.y) {
    if (target) target.dispose();
    target = new THREE.WebGLRenderTarget(size.x, size.y);
  }
  const colour = new THREE.Color();
  const saved = instanced.map(({ mesh }) => ({ material: mesh.material, colours: mesh.instanceColor }));
  const ids = instanced.map(({ mesh }) => mesh.userData.idColours);
  const background = world.background;
  instanced.forEach(({ mesh, items }, k) => {
    mesh.material = flat;
    if (!ids[k]) {  // made once per mesh and kept for the next call
      mesh.instanceColor = null;
      items.forEach((item, i) => {
        const id = item.body >= 0 ? item.body + 1 : 0;
        mesh.setColorAt(i, colour.setRGB((id & 255) / 255, ((id >> 8) & 255) / 255, 0, THREE.LinearSRGBColorSpace));
      });
      mesh.userData.idColours = mesh.instanceColor;
    }
    mesh.instanceColor = mesh.userData.idColours;
  });
  world.background = new THREE.Color(0, 0, 0);
  hiddenParts.forEach((o) => { o.visible = false; });
  renderer.setRenderTarget(target);
  renderer.render(world, camera);
  const pixels = new Uint8Array(size.x * size.y * 4);
  renderer.readRenderTargetPixels(target, 0, 0, size.x, size.y, pixels);
  renderer.setRenderTarget(null);
  hiddenParts.forEach((o) => { o.visible = true; });
  world.background = background;
  instanced.forEach(({ mesh }, k) => { mesh.material = saved[k].material; mesh.instanceColor = saved[k].colours; });

  const r = renderer.domElement.getBoundingClientRect();
  const sx = size.x / r.width, sy = size.y / r.height;
  const masked = (x, y) => hidden.some((h) => x >= (h.left - r.left) * sx && x < (h.right - r.left) * sx &&
                                             y >= (h.top - r.top) * sy && y < (h.bottom - r.top) * sy);
  const counts = new Array(bodyCount).fill(0);
  let unknown = 0;
  for (let row = 0; row < size.y; row++) {
    const y = size.y - 1 - row;  // the target's rows run bottom up
    for (let x = 0; x < size.x; x++) {
      const p = 4 * (row * size.x + x);
      const id = pixels[p] + 256 * pixels[p + 1];
      if (id === 0 || masked(x, y)) continue;
      if (id <= bodyCount) counts[id - 1]++;
      else unknown++;
    }
  }
  return { counts, unknown, pixelRatio: sx };
}
