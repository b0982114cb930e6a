// What README.md shows is what the build does. The blocks after its "README test" markers:
//   scene    — is scenes/first-room.json, byte for byte;
//   solve    — the command, run with the built binary (its -o file in a temporary directory);
//   summary  — what that command prints: the same lines and words, each number within 1e-3
//              relative (or both below 1e-6 in size: an imbalance at rounding level), except the
//              solve's time and the output path;
//   service  — with `lambert serve` started, its curl call takes the Cornell box as a job (202 with an
//              id), and the viewer's page is served at /?job=ID (tests/viewer_test.mjs opens it).
// Usage: node tests/readme_test.mjs REPO_ROOT LAMBERT_BINARY
import { execFileSync, spawn } from "node:child_process";
import { mkdtempSync, readFileSync, rmSync } from "node:fs";
import { tmpdir } from "node:os";
import { join, resolve } from "node:path";

const [root, lambert] = process.argv.slice(2).map((p) => resolve(p));
const readme = readFileSync(join(root, "README.md"), "utf8");
let passed = 0, failed = 0;
function check(ok, what) {
  console.log(`${ok ? "ok  " : "FAIL"} ${what}`);
  ok ? passed++ : failed++;
}

// The fenced block right after `<!-- README test: NAME -->`.
function block(name) {
  const m = readme.match(new RegExp(`<!-- README test: ${name} -->\\n\`\`\`[a-z]*\\n([\\s\\S]*?)\`\`\``));
  if (!m) throw new Error(`README.md has no block marked "${name}"`);
  return m[1];
}

const work = mkdtempSync(join(tmpdir(), "lambert-readme-test-"));
let server = null;
try {
  check(block("scene") === readFileSync(join(root, "scenes/first-room.json"), "utf8"), "the scene shown is scenes/first-room.json");

  const command = block("solve").trim().split(/\s+/);
  check(command[0] === "build/lambert" && command.at(-2) === "-o", `the command runs the built binary: ${command.join(" ")}`);
  const output = join(work, "result.json");
  const printed = execFileSync(lambert, [...command.slice(1, -1), output], { cwd: root, encoding: "utf8" });
  compareSummary(printed.trimEnd().split("\n"), block("summary").trimEnd().split("\n"), command.at(-1), output);
  check(JSON.parse(readFileSync(output, "utf8")).patches.length > 0, "it wrote the result");

  server = spawn(lambert, ["serve", "--port", "0", "--threads", "1"], { stdio: ["ignore", "pipe", "ignore"] });
  const url = await new Promise((done, fail) => {
    let out = "";
    server.stdout.on("data", (d) => (out += d).match(/http:\/\/\S+/) && done(out.match(/http:\/\/\S+/)[0]));
    server.on("exit", (code) => fail(new Error(`lambert serve exited (${code})`)));
  });
  const curl = block("service").split("\n").find((line) => line.startsWith("curl "));
  check(block("service").startsWith("build/lambert serve &") && curl.includes("http://127.0.0.1:8080/"),
        "the service block starts the server and calls its default address");
  const answer = JSON.parse(execFileSync("bash", ["-c", curl.replaceAll("http://127.0.0.1:8080", url)], { cwd: root, encoding: "utf8" }));
  check(typeof answer.id === "string" && ["queued", "running", "done"].includes(answer.state),
        `its curl call submitted a job: ${answer.id} (${answer.state})`);
  const page = await fetch(`${url}/?job=${answer.id}`);
  check(page.status === 200 && (await page.text()).includes("Lambert viewer"), "the viewer answers /?job=ID");
} catch (error) {
  check(false, `the test ran to its end: ${error.stack}`);
} finally {
  server?.kill("SIGTERM");
  rmSync(work, { recursive: true, force: true });
}
console.log(`${passed} passed, ${failed} failed`);
process.exit(failed === 0 ? 0 : 1);

function compareSummary(got, shown, shownPath, path) {
  check(got.length === shown.length, `the summary has the ${shown.length} lines shown (${got.length})`);
  const numeric = (t) => /^[-+]?\d/.test(t) && Number.isFinite(parseFloat(t));
  shown.forEach((line, k) => {
    const mine = (got[k] ?? "").replace(path, shownPath);
    const a = line.split(/\s+/), b = mine.split(/\s+/);
    const same = a.length === b.length && a.every((word, q) => {
      if (k === 0 && a[q + 1] === "s") return numeric(b[q]); // the solve's time
      if (!numeric(word)) return word === b[q];
      const x = parseFloat(word), y = parseFloat(b[q]);
      return (Math.abs(x) < 1e-6 && Math.abs(y) < 1e-6) || Math.abs(x - y) <= 1e-3 * Math.max(Math.abs(x), Math.abs(y));
    });
    check(same, `summary line ${k + 1}: "${mine}"${same ? "" : ` against "${line}"`}`);
  });
}
