#!/usr/bin/env bash
# The contract documents against independent validators (tests/schema_test.mjs): every scene in
# scenes/ against docs/scene.schema.json with Ajv, and docs/openapi.json as OpenAPI 3.1.
# Needs node and tools/node_modules (tools/install-deps.sh installs both).
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
if ! command -v node >/dev/null 2>&1; then
  echo "schema_test: node is not installed; run tools/install-deps.sh" >&2
  exit 1
fi
exec node "$root/tests/schema_test.mjs" "$root"
