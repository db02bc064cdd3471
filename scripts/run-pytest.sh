#!/usr/bin/env bash
# Runs every Python test (tools and end-to-end SIL) in the project's venv.
set -uo pipefail
cd "$(dirname "$0")/.."
.venv/bin/python -m pytest -q "$@" tests
rc=$?
if [ "$rc" -eq 5 ]; then
  echo "pytest: no Python tests collected" >&2
fi
exit "$rc"
