#!/usr/bin/env bash
# `make sil`: irassi_large with every IRASSI law through real processes (plant_node,
# fsw_node, LCM recorder) in a private network namespace, reference and realistic
# actuators, then the comparison table and where the plots are (aocs_runner.demo).
set -euo pipefail
cd "$(dirname "$0")/.."
exec .venv/bin/python -m aocs_runner.demo "$@"
