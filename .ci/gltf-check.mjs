// Check every .glb given on the command line twice: the Khronos glTF validator must report
// 0 errors and 0 warnings, and three.js's GLTFLoader (the loader most web viewers use) must
// load it in Node, without a browser, with no error or console warning, a node named
// `stock` and non-empty bounds.
// usage: (cd DIR_WITH_node_modules && node .../.ci/gltf-check.mjs file.glb [...])
// where gltf-validator and three are installed.
import { readFileSync } from "node:fs";
import { createRequire } from "node:module";
import { dirname } from "node:path";
import { pathToFileURL } from "node:url";
// The ES module build, the same instance GLTFLoader imports.
const require = createRequire(process.cwd() + "/");
const root = dirname(dirname(require.resolve("three")));
const three = await import(pathToFileURL(root + "/build/three.module.js"));
const { GLTFLoader } = await import(pathToFileURL(root + "/examples/jsm/loaders/GLTFLoader.js"));
const validator = require("gltf-validator");
let bad = 0;
const warn = console.warn;
for (const f of process.argv.slice(2)) {
  const complaints = [];
  const b = readFileSync(f);
  const report = await validator.validateBytes(new Uint8Array(b));
  const issues = report.issues;
  for (const m of issues.messages.filter((m) => m.severity <= 1).slice(0, 10)) {
    complaints.push(`validator ${m.severity === 0 ? "error" : "warning"} ${m.code}: ${m.message} (${m.pointer || ""})`);
  }
  if (issues.numErrors + issues.numWarnings > 0) {
    complaints.push(`validator: ${issues.numErrors} errors, ${issues.numWarnings} warnings`);
  }
  console.warn = (...a) => complaints.push(a.join(" "));
  const ab = b.buffer.slice(b.byteOffset, b.byteOffset + b.byteLength);
  try {
    const gltf = await new Promise((ok, fail) => new GLTFLoader().parse(ab, "", ok, fail));
    const names = [];
    let tris = 0, lines = 0;
    gltf.scene.traverse((o) => {
      if (o.name) names.push(o.name);
      if (o.isMesh) tris += (o.geometry.index ? o.geometry.index.count : o.geometry.attributes.position.count) / 3;
      if (o.isLine) lines += 1;
    });
    const box = new three.Box3().setFromObject(gltf.scene);
    if (!names.includes("stock")) complaints.push("no node named stock");
    if (!(box.max.z > box.min.z)) complaints.push("empty bounds");
    console.warn = warn;
    const nodes = [...new Set(names.filter((n) => !/_\d+$/.test(n)))].join(", ");
    const size = (box.max.z - box.min.z).toFixed(4);
    console.log(`${f}: validator ${issues.numErrors} errors, ${issues.numWarnings} warnings, ${issues.numInfos} infos; three.js: ${tris} triangles, ${lines} lines, nodes ${nodes}, ${size} m long`);
  } catch (e) {
    complaints.push(String(e));
  }
  console.warn = warn;
  if (complaints.length) {
    bad = 1;
    console.log(`${f}: ${complaints.join("; ")}`);
  }
}
process.exit(bad);
