#!/usr/bin/env bash
# refrax bench tracer beside the rqprobe k-buffer (../shared/tools/rqprobe), same scenes, one run.
# Usage: bench/tracer.sh [extra refrax bench options]   (build first)
set -euo pipefail
cd "$(dirname "$0")/.."
shared=${REFRAX_SHARED:-../shared}
probe_dir=build/rqprobe
if [ ! -x "$probe_dir/rqprobe" ]; then
  rm -rf "$probe_dir" && mkdir -p "$probe_dir"
  cp -r "$shared/tools/rqprobe/." "$probe_dir/"
  chmod -R u+w "$probe_dir"
  (cd "$probe_dir" && sh build.sh >/dev/null)
fi
mkdir -p bench/results
device=$(./build/refrax devices | sed -n 's/^\[0\] \([^(]*\).*/\1/p' | tr -c 'A-Za-z0-9\n' '_' | sed 's/_*$//')
./build/refrax bench tracer --probe "$PWD/$probe_dir/rqprobe" --out "bench/results/tracer_${device:-device}.json" "$@"
