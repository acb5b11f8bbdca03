// The reference counts of mesh_bench from the npm packages themselves: Martini's RTIN made
// strict by the samples and Delatin's greedy Delaunay, on the crop mesh_bench writes. Not part
// of the build or the tests, and nothing here is installed by them:
//
//   mesh_bench --write-crop /tmp/crop.f32          # 513 x 513 float32, rows north first
//   mkdir /tmp/ref && cd /tmp/ref && npm install @mapbox/martini delatin
//   node --experimental-default-type=module $POLDER/tests/bench/mesh_reference.mjs /tmp/crop.f32 [2,5,10]
//
// (run from the folder holding node_modules, or set NODE_PATH). Both packages measure error at
// the samples only: Delatin refines until no sample is farther than the bound from its
// triangle; Martini's own threshold only bounds its midpoint errors, so the largest threshold
// whose mesh keeps every sample within the bound is searched, as mesh_bench does.
import fs from 'fs';
import path from 'path';
import { createRequire } from 'module';

const require = createRequire(path.join(process.cwd(), 'noop.js'));
const Martini = require('@mapbox/martini').default ?? require('@mapbox/martini');
const Delatin = require('delatin').default ?? require('delatin');

const [cropFile, boundsText = '2,5,10'] = process.argv.slice(2);
const bytes = fs.readFileSync(cropFile);
const heights = new Float32Array(bytes.buffer, bytes.byteOffset, bytes.length / 4);
const size = Math.round(Math.sqrt(heights.length));
if (size * size !== heights.length) throw new Error('the crop is not square');

// Largest |sample - plane| over the samples in each closed triangle (x, y image coordinates).
function samplesMaxError(coords, triangles) {
  let worst = 0;
  for (let t = 0; t < triangles.length; t += 3) {
    const ax = coords[2 * triangles[t]], ay = coords[2 * triangles[t] + 1];
    const bx = coords[2 * triangles[t + 1]], by = coords[2 * triangles[t + 1] + 1];
    const cx = coords[2 * triangles[t + 2]], cy = coords[2 * triangles[t + 2] + 1];
    const det = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
    if (det === 0) continue;
    const za = heights[ay * size + ax], zb = heights[by * size + bx], zc = heights[cy * size + cx];
    for (let y = Math.min(ay, by, cy); y <= Math.max(ay, by, cy); y++) {
      for (let x = Math.min(ax, bx, cx); x <= Math.max(ax, bx, cx); x++) {
        const w0 = ((bx - x) * (cy - y) - (by - y) * (cx - x)) / det;
        const w1 = ((cx - x) * (ay - y) - (cy - y) * (ax - x)) / det;
        const w2 = 1 - w0 - w1;
        if (w0 < -1e-12 || w1 < -1e-12 || w2 < -1e-12) continue;
        worst = Math.max(worst, Math.abs(heights[y * size + x] - (w0 * za + w1 * zb + w2 * zc)));
      }
    }
  }
  return worst;
}

const martini = new Martini(size);
const tile = martini.createTile(heights);
const thresholds = [...new Set(tile.errors)].sort((a, b) => a - b);
for (const bound of boundsText.split(',').map(Number)) {
  let lo = 0, hi = thresholds.length, best = null;
  while (lo < hi) {
    const mid = (lo + hi) >> 1;
    const mesh = tile.getMesh(thresholds[mid]);
    const error = samplesMaxError(mesh.vertices, mesh.triangles);
    if (error <= bound) {
      best = { threshold: thresholds[mid], triangles: mesh.triangles.length / 3, error };
      lo = mid + 1;
    } else {
      hi = mid;
    }
  }
  const tin = new Delatin(heights, size, size);
  tin.run(bound);
  console.log(JSON.stringify({
    bound_m: bound,
    martini_strict_triangles: best ? best.triangles : null,
    martini_strict_threshold_m: best ? best.threshold : null,
    martini_strict_samples_error_m: best ? best.error : null,
    delatin_triangles: tin.triangles.length / 3,
    delatin_samples_error_m: tin.getMaxError(),
  }));
}
