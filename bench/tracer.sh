#!/usr/bin/env bash
# refrax bench tracer beside the rqprobe k-buffer (../shared/tools/rqprobe), same scenes, one run.
# Usage: bench/tracer.sh [extra refrax bench options]   (build first)
set -euo pipefail
cd "$(dirname "$0")/.."
. bench/build-probe.sh
./build/refrax bench tracer --probe "$probe" --out "bench/results/tracer_${device:-device}.json" "$@"
