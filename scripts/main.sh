#!/usr/bin/env bash
# One command for a fresh Debian 12 machine: install dependencies, build,
# render the default CONOPS dataset (x16 MSAA, with calibration pairs),
# analyze it with the shelled reference model and print the per-region table.
# Usage: bash scripts/main.sh [DATASET_DIR]   (default datasets/conops-x16)
set -euo pipefail
cd "$(dirname "$0")/.."
dataset="${1:-datasets/conops-x16}"
bash scripts/install-deps.sh
bash scripts/build.sh
build/renderer/aar-render calib "$dataset" --msaa 16
build/renderer/aar-render render "$dataset" --msaa 16
out="results/$(basename "$dataset")-shelled"
build/analyzer/aar-analyze run "$dataset" --model shelled --out "$out"
cat "$out/summary.md"
