// Validates glTF binary files with the Khronos glTF validator (npm gltf-validator, pinned in
// tools/package-lock.json). Prints every message; exits 1 when a file has an error or a warning.
// Usage: node tests/gltf_validate.mjs REPO_ROOT FILE.glb...
import { readFileSync } from "node:fs";
import { join, resolve } from "node:path";
import { pathToFileURL } from "node:url";

const [root, ...files] = process.argv.slice(2);
const { validateBytes, version } = await import(
  pathToFileURL(join(resolve(root), "tools", "node_modules", "gltf-validator", "module.mjs")).href);
let bad = 0;
for (const file of files) {
  const report = await validateBytes(new Uint8Array(readFileSync(file)));
  const { numErrors, numWarnings, numInfos, numHints, messages } = report.issues;
  console.log(`${file}: ${numErrors} errors, ${numWarnings} warnings, ${numInfos} infos, ${numHints} hints ` +
              `(gltf-validator ${version()})`);
  for (const m of messages) console.log(`  ${["error", "warning", "info", "hint"][m.severity]} ${m.code} ${m.pointer ?? ""}: ${m.message}`);
  if (numErrors > 0 || numWarnings > 0) bad++;
  const triangles = report.info?.totalTriangleCount ?? 0;
  console.log(`  ${report.info?.drawCallCount ?? 0} draw calls, ${triangles} triangles`);
  if (!(triangles > 0)) {
    console.log("  the file draws nothing");
    bad++;
  }
}
process.exit(bad === 0 ? 0 : 1);
