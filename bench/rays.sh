#!/usr/bin/env bash
# refrax bench rays beside the rqprobe floor (../shared/tools/rqprobe), same scenes, one run.
# Usage: bench/rays.sh [extra refrax bench options]   (build first: scripts/test.sh or demo.sh)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/build-probe.sh
./build/refrax bench rays --probe "$probe" --out "bench/results/rays_${device:-device}.json" "$@"
