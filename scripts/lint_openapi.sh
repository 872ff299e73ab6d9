#!/usr/bin/env bash
# Lints schema/openapi.yaml with the pinned Redocly CLI (package.json; run `npm ci` at the
# repository root first). Rules: redocly.yaml; accepted findings: .redocly.lint-ignore.yaml.
# Exits non-zero on any error.
set -euo pipefail
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
REDOCLY=$ROOT/node_modules/.bin/redocly
[ -x "$REDOCLY" ] || { echo "lint_openapi: no $REDOCLY: run 'npm ci' in $ROOT" >&2; exit 2; }
cd "$ROOT"
# No usage data to Redocly, no look-up of newer versions.
export REDOCLY_TELEMETRY=off REDOCLY_SUPPRESS_UPDATE_NOTICE=true
"$REDOCLY" lint --config redocly.yaml schema/openapi.yaml
