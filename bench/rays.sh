#!/usr/bin/env bash
# refrax bench rays beside the rqprobe floor (../shared/tools/rqprobe), same scenes, one run.
# Usage: bench/rays.sh [extra refrax bench options]   (build first: scripts/test.sh or demo.sh)
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
./build/refrax bench rays --probe "$PWD/$probe_dir/rqprobe" --out "bench/results/rays_${device:-device}.json" "$@"
