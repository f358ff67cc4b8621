#!/usr/bin/env bash
# The main job on the bundled example: install what is missing, build, then run it.
# (Today: the device self-test and the ray-query benchmark; it grows into
# synthesise -> train -> render -> report as those stages land.)
set -euo pipefail
cd "$(dirname "$0")/.."
[ "${REFRAX_SKIP_INSTALL:-0}" = 1 ] || bash scripts/install-deps.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
cmake --build build -j"$(nproc)"
./build/refrax devices
./build/refrax selftest --validation
