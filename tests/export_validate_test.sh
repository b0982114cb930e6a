#!/usr/bin/env bash
# Every glTF file Lambert exports, through the Khronos glTF validator (tests/gltf_validate.mjs):
# `lambert export` of the bundled Cornell box, smooth and flat, and GET /v1/jobs/{id}/result.glb
# from a running `lambert serve` (both shadings), which must be the same bytes as the command's.
# Also checks that the PLY and CSV exports are written. Needs node, curl and tools/node_modules
# (tools/install-deps.sh). Usage: export_validate_test.sh LAMBERT_BINARY
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
lambert="$1"
for tool in node curl; do
  command -v "$tool" >/dev/null 2>&1 || { echo "export_validate_test: $tool is missing; run tools/install-deps.sh" >&2; exit 1; }
done
[ -d "$root/tools/node_modules/gltf-validator" ] ||
  { echo "export_validate_test: tools/node_modules/gltf-validator is missing; run tools/install-deps.sh" >&2; exit 1; }

work="$(mktemp -d)"
server_pid=""
cleanup() {
  if [ -n "$server_pid" ]; then kill "$server_pid" 2>/dev/null || true; wait "$server_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

"$lambert" solve "$root/scenes/cornell-box.json" -o "$work/cornell.json" > /dev/null
"$lambert" export "$work/cornell.json" -o "$work/smooth.glb"
"$lambert" export "$work/cornell.json" -o "$work/flat.glb" --shading flat
"$lambert" export "$work/cornell.json" -o "$work/cornell.ply"
"$lambert" export "$work/cornell.json" -o "$work/cornell.csv"
head -c 3 "$work/cornell.ply" | grep -q ply
[ "$(wc -l < "$work/cornell.csv")" -eq 82 ]  # header + the 9 × 9 floor grid

# The service: the same scene as a job, its result.glb in both shadings.
"$lambert" serve --port 0 --threads 1 > "$work/serve.out" 2> "$work/serve.err" &
server_pid=$!
for _ in $(seq 100); do grep -q "listening on" "$work/serve.out" 2>/dev/null && break; sleep 0.1; done
url="$(grep -o 'http://[^ ]*' "$work/serve.out")"
[ -n "$url" ] || { cat "$work/serve.err"; exit 1; }
id="$(curl -sf -X POST -H 'Content-Type: application/json' --data-binary @"$root/scenes/cornell-box.json" \
        "$url/v1/jobs" | node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.parse(s).id))')"
for _ in $(seq 600); do
  state="$(curl -sf "$url/v1/jobs/$id" | node -e 'let s="";process.stdin.on("data",d=>s+=d).on("end",()=>console.log(JSON.parse(s).state))')"
  [ "$state" = done ] && break
  [ "$state" = failed ] && { echo "the job failed"; exit 1; }
  sleep 0.1
done
curl -sf -o "$work/http-smooth.glb" "$url/v1/jobs/$id/result.glb"
curl -sf -o "$work/http-flat.glb" "$url/v1/jobs/$id/result.glb?shading=flat"
curl -sf -o "$work/http.json" "$url/v1/jobs/$id/result"
# The route converts the stored result as the command does: the same bytes from the same result.
"$lambert" export "$work/http.json" -o "$work/from-http-json.glb"
cmp "$work/http-smooth.glb" "$work/from-http-json.glb"
status="$(curl -s -o /dev/null -w '%{http_code}' "$url/v1/jobs/$id/result.glb?shading=glossy")"
[ "$status" = 400 ] || { echo "result.glb?shading=glossy answered $status, not 400"; exit 1; }
status="$(curl -s -o /dev/null -w '%{http_code}' "$url/v1/jobs/0123456789abcdef0123456789abcdef/result.glb")"
[ "$status" = 404 ] || { echo "result.glb of an unknown job answered $status, not 404"; exit 1; }
[ "$(curl -s "$url/v1/jobs/$id/result.csv" | wc -l)" -eq 82 ]

node "$root/tests/gltf_validate.mjs" "$root" "$work/smooth.glb" "$work/flat.glb" "$work/http-smooth.glb" "$work/http-flat.glb"
