// Checks the contract documents with validators independent of Lambert's C++ decoder:
//   - docs/scene.schema.json compiles as JSON Schema 2020-12 under Ajv's strict mode, accepts every
//     scene in scenes/ (recursively) and rejects a set of scenes the decoder rejects too;
//   - docs/openapi.json parses, validates against the OpenAPI 3.1 schema
//     (@seriousme/openapi-schema-validator) and describes every route of SPEC §4.
// The npm packages live in tools/node_modules (tools/install-deps.sh installs them from
// tools/package-lock.json). Usage: node tests/schema_test.mjs [repository root]
import { createRequire } from "node:module";
import { readFileSync, readdirSync, statSync, existsSync } from "node:fs";
import { join, relative, resolve, dirname } from "node:path";
import { fileURLToPath, pathToFileURL } from "node:url";

const root = resolve(process.argv[2] ?? join(dirname(fileURLToPath(import.meta.url)), ".."));
const tools = join(root, "tools");
if (!existsSync(join(tools, "node_modules", "ajv"))) {
  console.error("schema_test: tools/node_modules is missing; run tools/install-deps.sh");
  process.exit(1);
}
const require = createRequire(join(tools, "package.json"));
const Ajv2020 = require("ajv/dist/2020").default;
const addFormats = require("ajv-formats").default;
const { Validator } = await import(
  pathToFileURL(join(tools, "node_modules", "@seriousme", "openapi-schema-validator", "index.js")).href
);

let passed = 0;
let failed = 0;
function check(ok, what, detail = "") {
  if (ok) {
    passed++;
    console.log(`ok    ${what}`);
  } else {
    failed++;
    console.log(`FAIL  ${what}${detail ? "\n      " + detail : ""}`);
  }
}
const readJson = (path) => JSON.parse(readFileSync(path, "utf8"));

// ---- scene schema ------------------------------------------------------------------------------
// Strict mode catches unknown keywords and misplaced constraints in the schema itself; only its
// "required names a property defined elsewhere" rule is relaxed, since oneOf [{required: [a]},
// {required: [b]}] beside "properties" is the standard way to say "exactly one of a, b".
const ajv = new Ajv2020({ strict: true, strictRequired: false, allErrors: true });
addFormats(ajv);
let validateScene;
try {
  validateScene = ajv.compile(readJson(join(root, "docs", "scene.schema.json")));
  check(true, "docs/scene.schema.json compiles (JSON Schema 2020-12, Ajv strict mode)");
} catch (e) {
  check(false, "docs/scene.schema.json compiles", e.message);
}

function sceneFiles(dir) {
  const out = [];
  for (const name of readdirSync(dir).sort()) {
    const path = join(dir, name);
    if (statSync(path).isDirectory()) out.push(...sceneFiles(path));
    else if (name.endsWith(".json")) out.push(path);
  }
  return out;
}

if (validateScene) {
  const files = sceneFiles(join(root, "scenes"));
  check(files.length > 0, `scenes/ has scene files (${files.length})`);
  for (const file of files) {
    const ok = validateScene(readJson(file));
    check(ok, `valid: ${relative(root, file)}`, ok ? "" : ajv.errorsText(validateScene.errors));
  }

  const floor = [[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]];
  const base = () => ({
    materials: { white: { reflectance: 0.5 } },
    surfaces: [{ name: "floor", material: "white", polygon: floor }],
  });
  const accepted = {
    "the minimal scene": base(),
    "every light type": Object.assign(base(), {
      lights: [
        { type: "ambient", irradiance: 0.01 },
        { type: "directional", direction: [0, -1, 0], irradiance: { cie: "D65" }, illuminance_lx: 10000 },
        { type: "point", position: [0.5, 2, 0.5], intensity: { blackbody_K: 2856 }, luminous_intensity_cd: 100,
          attenuation: { c1: 1, c2: 0.1, c3: 0.01 } },
        { type: "goniometric", position: [0, 2, 0], axis: [0, -1, 0], intensity: 5, exponent: 4 },
        { type: "spot", position: [0, 2, 0], axis: [0, -1, 0], intensity: 5, exponent: 20, cutoff_deg: 30 },
        { type: "warn", position: [0, 2, 0], axis: [0, -1, 0], intensity: 5 },
      ],
    }),
    "a file surface with a transform and a Phong emitter": Object.assign(base(), {
      surfaces: [{ name: "statue", material: "white", file: "meshes/statue.ply",
                   transform: { scale: 0.01, rotate_deg: [0, 90, 0], translate: [1, 0, 2] },
                   emission: { exitance: { cie: "D65" }, luminous_exitance_lm_m2: 1000, lobe: { phong: 8 } } }],
    }),
    "grid probes and options": Object.assign(base(), {
      probes: [{ name: "wp", grid: { origin: [0, 0.75, 0], u: [1, 0, 0], v: [0, 0, 1], nu: 10, nv: 10 }, normal: [0, 1, 0] }],
      meshing: { max_patch_area: 0.01, adaptive: true }, solver: { tolerance: 1e-4 }, output: { spectral: false },
      spectrum: { mode: "spectral", wavelengths_nm: [450, 550, 650] },
    }),
  };
  for (const [what, scene] of Object.entries(accepted)) {
    const ok = validateScene(scene);
    check(ok, `accepts ${what}`, ok ? "" : ajv.errorsText(validateScene.errors));
  }

  const rejected = {
    "an unknown top-level key": Object.assign(base(), { colour: "red" }),
    "an unknown surface key": Object.assign(base(), { surfaces: [{ material: "white", polygon: floor, colour: 1 }] }),
    "a reflectance above 1": Object.assign(base(), { materials: { white: { reflectance: 1.2 } } }),
    "a negative emission": Object.assign(base(), { lights: [{ type: "ambient", irradiance: -1 }] }),
    "no materials": { surfaces: base().surfaces },
    "an empty surface list": Object.assign(base(), { surfaces: [] }),
    "a surface with polygon and mesh": Object.assign(base(), {
      surfaces: [{ material: "white", polygon: floor, mesh: { vertices: floor, triangles: [[0, 1, 2]] } }],
    }),
    "a transform on a polygon": Object.assign(base(), {
      surfaces: [{ material: "white", polygon: floor, transform: { scale: 2 } }],
    }),
    "an unknown light type": Object.assign(base(), { lights: [{ type: "laser", position: [0, 1, 0], intensity: 1 }] }),
    "a point light with an axis": Object.assign(base(), {
      lights: [{ type: "point", position: [0, 1, 0], intensity: 1, axis: [0, -1, 0] }],
    }),
    "two totals on one light": Object.assign(base(), {
      lights: [{ type: "point", position: [0, 1, 0], intensity: 1, luminous_intensity_cd: 1, luminous_flux_lm: 2 }],
    }),
    "a total that does not apply": Object.assign(base(), {
      lights: [{ type: "point", position: [0, 1, 0], intensity: 1, illuminance_lx: 5 }],
    }),
    "a zero direction": Object.assign(base(), { lights: [{ type: "directional", direction: [0, 0, 0], irradiance: 1 }] }),
    "a coordinate beyond 1e9": Object.assign(base(), {
      surfaces: [{ material: "white", polygon: [[0, 0, 0], [2e9, 0, 0], [0, 0, 1]] }],
    }),
    "a probe without a normal": Object.assign(base(), { probes: [{ position: [0, 0, 0] }] }),
    "a fractional grid size": Object.assign(base(), {
      probes: [{ grid: { origin: [0, 0, 0], u: [1, 0, 0], v: [0, 0, 1], nu: 1.5, nv: 2 }, normal: [0, 1, 0] }],
    }),
    "format version 2": Object.assign(base(), { lambert: 2 }),
    "a unit of feet": Object.assign(base(), { units: "ft" }),
    "an rgb emission": Object.assign(base(), { lights: [{ type: "ambient", irradiance: { rgb: [1, 1, 1] } }] }),
    "a spectrum with two forms": Object.assign(base(), { materials: { white: { reflectance: { cie: "A", blackbody_K: 3000 } } } }),
    "an emission with exitance and radiance": Object.assign(base(), {
      surfaces: [{ material: "white", polygon: floor, emission: { exitance: 1, radiance: 1 } }],
    }),
  };
  for (const [what, scene] of Object.entries(rejected)) {
    const ok = !validateScene(scene);
    check(ok, `rejects ${what}`);
  }
}

// ---- OpenAPI -------------------------------------------------------------------------------------
const openapiPath = join(root, "docs", "openapi.json");
let openapi;
try {
  openapi = readJson(openapiPath);
  check(true, "docs/openapi.json parses");
} catch (e) {
  check(false, "docs/openapi.json parses", e.message);
}
if (openapi) {
  const validator = new Validator();
  const result = await validator.validate(openapi);
  check(result.valid && validator.version === "3.1", "docs/openapi.json is valid OpenAPI 3.1",
        JSON.stringify(result.errors ?? validator.version).slice(0, 2000));
  const broken = structuredClone(openapi);
  delete broken.paths["/v1/health"].get.responses["200"].description;
  check(!(await new Validator().validate(broken)).valid, "the OpenAPI validator rejects a response without description");

  const routes = {
    "/v1/solve": ["post"], "/v1/jobs": ["post"], "/v1/jobs/{id}": ["get", "delete"],
    "/v1/jobs/{id}/result": ["get"], "/v1/jobs/{id}/result.glb": ["get"], "/v1/jobs/{id}/result.ply": ["get"],
    "/v1/jobs/{id}/result.csv": ["get"], "/v1/health": ["get"], "/v1/metrics": ["get"], "/v1/openapi.json": ["get"],
    "/v1/schema/scene.json": ["get"], "/": ["get"],
  };
  const paths = openapi.paths ?? {};
  check(JSON.stringify(Object.keys(paths).sort()) === JSON.stringify(Object.keys(routes).sort()),
        "docs/openapi.json has exactly the served routes", Object.keys(paths).join(", "));
  for (const [path, methods] of Object.entries(routes))
    for (const m of methods) {
      const op = paths[path]?.[m];
      check(op && op.operationId && op.responses && Object.keys(op.responses).length > 0,
            `docs/openapi.json describes ${m.toUpperCase()} ${path}`);
    }
  const codes = (openapi.components?.schemas?.Error?.properties?.error?.properties?.code?.enum) ?? [];
  for (const code of ["invalid_json", "invalid_scene", "too_large", "not_found", "queue_full", "not_done"])
    check(codes.includes(code), `docs/openapi.json lists the error code ${code}`);
}

console.log(`\nschema_test: ${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);
