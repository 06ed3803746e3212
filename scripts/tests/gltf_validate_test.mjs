// The Khronos glTF validator (npm gltf-validator, pinned in scripts/web)
// reports no error on any .glb of a fit report.
//   node scripts/tests/gltf_validate_test.mjs REPORT_DIR
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

const require = createRequire(import.meta.url);
const web = path.join(path.dirname(new URL(import.meta.url).pathname), '..', 'web', 'node_modules');
if (!fs.existsSync(path.join(web, 'gltf-validator'))) {
  console.error(`gltf-validator is not installed in ${web}: run \`make deps\``);
  process.exit(1);
}
const validator = require(path.join(web, 'gltf-validator'));

const report = process.argv[2];
const models = path.join(report, 'models');
const files = fs.readdirSync(models).filter((f) => f.endsWith('.glb')).sort();
if (files.length < 3) {
  console.error(`expected the key poses' and the rest shape's .glb files in ${models}, found ${files.length}`);
  process.exit(1);
}
let failed = 0;
for (const f of files) {
  const bytes = new Uint8Array(fs.readFileSync(path.join(models, f)));
  const result = await validator.validateBytes(bytes, { uri: f, maxIssues: 50 });
  const i = result.issues;
  console.log(`${f}: ${i.numErrors} errors, ${i.numWarnings} warnings, ${i.numInfos} infos, ` +
              `${result.info.totalVertexCount} vertices, ${result.info.totalTriangleCount} triangles`);
  for (const m of i.messages) if (m.severity <= 1) console.log(`  ${m.severity === 0 ? 'error' : 'warning'} ${m.code}: ${m.message} (${m.pointer || ''})`);
  if (i.numErrors > 0) failed++;
}
// The poses' files hold the body and the garment with its stretch.
const pose = files.find((f) => f.startsWith('pose_'));
const glb = fs.readFileSync(path.join(models, pose));
const json = JSON.parse(glb.subarray(20, 20 + glb.readUInt32LE(12)).toString('utf8'));
const names = json.nodes.map((n) => n.name);
const garment = json.meshes[names.indexOf('garment')];
if (!names.includes('body') || !garment || !('_MAX_STRETCH' in garment.primitives[0].attributes) ||
    !('COLOR_0' in garment.primitives[0].attributes)) {
  console.error(`${pose}: expected the meshes body and garment with COLOR_0 and _MAX_STRETCH, found ${JSON.stringify(names)}`);
  failed++;
}
console.log(`${files.length - failed} passed, ${failed} failed`);
process.exit(failed ? 1 : 0);
