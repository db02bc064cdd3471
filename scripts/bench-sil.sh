#!/usr/bin/env bash
# `make bench`: the SIL lockstep benchmark (tools/aocs/bench_sil.py): irassi_large through
# real processes over LCM, the bare transport round trip, the plant in process, the ratio.
set -euo pipefail
cd "$(dirname "$0")/.."
exec .venv/bin/python -m aocs.bench_sil "$@"
