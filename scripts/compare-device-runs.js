#!/usr/bin/env node
// Compares two sarloc-mission summaries (--json) of one mission and seed in which one rescuer's
// device ran from different builds (scripts/build-arm64: amd64, then arm64 under qemu).
//   node scripts/compare-device-runs.js REFERENCE.json OTHER.json RESCUER_ID
// Passes (exit 0) when both found every victim, the rescuer found the same victims in both,
// each within 0.5 m by its own estimate, and the picture placed each of those victims in the two
// runs within the sum of its two stated 95 % radii. DDS timing differs between runs, so the
// estimates agree within what they state, not to the bit. Prints one line per victim.
"use strict";
const fs = require("fs");
const [refPath, otherPath, rescuer] = process.argv.slice(2);
if (!refPath || !otherPath || !rescuer) {
  console.error("usage: compare-device-runs.js REFERENCE.json OTHER.json RESCUER_ID");
  process.exit(2);
}
const load = (p) => JSON.parse(fs.readFileSync(p, "utf8"));
const ref = load(refPath), other = load(otherPath);
const problems = [];
for (const [name, run] of [["reference", ref], ["other", other]]) {
  if (!run.all_found) problems.push(`${name} run: not every victim found`);
}
const radiusOf = (run, v) => {
  const fused = (run.fused_victims || []).find((f) => f.victim_id === v.victim_id && f.position.every((x, k) => x === v.estimate[k]));
  return fused ? fused.radius95_m : NaN;
};
const distance = (a, b) => Math.hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
for (const v of ref.victims) {
  const w = other.victims.find((x) => x.name === v.name);
  if (!w) { problems.push(`victim ${v.name}: missing from the other run`); continue; }
  const byRef = v.finders.includes(rescuer), byOther = w.finders.includes(rescuer);
  let line = `victim ${v.name}: found by ${rescuer}: ${byRef ? "yes" : "no"} / ${byOther ? "yes" : "no"}`;
  if (byRef !== byOther) problems.push(`victim ${v.name}: ${rescuer} found it in one run only`);
  if (byRef && byOther) {
    for (const [name, x] of [["reference", v], ["other", w]]) {
      if (!(x.relative_error_m <= 0.5)) problems.push(`victim ${v.name}: ${rescuer}'s own error ${x.relative_error_m} m in the ${name} run`);
    }
    const apart = distance(v.estimate, w.estimate), allowed = radiusOf(ref, v) + radiusOf(other, w);
    line += `; own error ${v.relative_error_m.toFixed(2)} / ${w.relative_error_m.toFixed(2)} m; picture positions ${apart.toFixed(2)} m apart (allowed ${allowed.toFixed(2)} m)`;
    if (!(apart <= allowed)) problems.push(`victim ${v.name}: placed ${apart.toFixed(2)} m apart, more than the radii's ${allowed.toFixed(2)} m`);
  }
  console.log(line);
}
// A device that found nothing proves nothing: the reference run's rescuer must have found one.
if (!ref.victims.some((v) => v.finders.includes(rescuer))) problems.push(`${rescuer} found no victim in the reference run`);
if (problems.length) {
  for (const p of problems) console.error(`compare-device-runs: ${p}`);
  process.exit(1);
}
console.log(`compare-device-runs: ${rescuer}'s device agrees between the two runs`);
