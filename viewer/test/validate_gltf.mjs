// The Khronos glTF validator (npm gltf-validator) on every .glb given: any error or
// warning fails. Usage: node validate_gltf.mjs FILE.glb...
import { readFileSync } from 'node:fs';
import { basename } from 'node:path';
import validator from 'gltf-validator';

const files = process.argv.slice(2);
if (files.length === 0) { console.error('usage: validate_gltf.mjs FILE.glb...'); process.exit(2); }
let failed = 0;
for (const file of files) {
  const report = await validator.validateBytes(new Uint8Array(readFileSync(file)), { uri: basename(file), maxIssues: 50 });
  const { numErrors, numWarnings, numInfos, messages } = report.issues;
  const info = report.info || {};
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos; ` +
              `${info.nodeCount ?? '?'} nodes, ${info.animationCount ?? 0} animations, ${info.totalVertexCount ?? '?'} vertices`);
  for (const m of messages) if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code} ${m.pointer ?? ''}: ${m.message}`);
  if (numErrors > 0 || numWarnings > 0) failed++;
}
console.log(`${files.length - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
