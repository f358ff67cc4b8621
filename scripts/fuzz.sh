#!/usr/bin/env bash
# Fuzzes every loader of user files (fuzz/README.md) with libFuzzer under ASan+UBSan.
#   scripts/fuzz.sh                 each target for 2,000 executions from the seed corpus (CI's regression pass)
#   scripts/fuzz.sh --runs N        N executions per target (the issue's bar: 1,000,000)
#   scripts/fuzz.sh --target NAME   one target (blender water_json npy ply gltf png checkpoint height_field colmap)
# The seed corpus is made by build/refrax (built by scripts/test.sh or scripts/demo.sh first);
# what a run finds is left in build-fuzz/findings/. Prints each target's executions.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=2000
targets=(blender water_json npy ply gltf png checkpoint height_field colmap)
while [ $# -gt 0 ]; do
  case $1 in
    --runs) [[ ${2:-} =~ ^[0-9]+$ ]] || { echo "fuzz: --runs needs a count" >&2; exit 2; }; runs=$2; shift ;;
    --target) case " ${targets[*]} " in *" ${2:-} "*) targets=("$2") ;; *) echo "fuzz: --target is one of ${targets[*]}" >&2; exit 2 ;; esac; shift ;;
    -h|--help) sed -n '2,7p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "fuzz: unknown option '$1' (--runs N, --target NAME)" >&2; exit 2 ;;
  esac
  shift
done
[ "${REFRAX_SKIP_INSTALL:-0}" = 1 ] || bash scripts/install-deps.sh
[ -x build/refrax ] || { echo "fuzz: build/refrax is missing (scripts/test.sh builds it): it makes the seed corpus" >&2; exit 2; }
cmake -S fuzz -B build-fuzz -DCMAKE_C_COMPILER=clang-14 -DCMAKE_CXX_COMPILER=clang++-14 -DCMAKE_BUILD_TYPE=RelWithDebInfo > /dev/null
cmake --build build-fuzz -j"$(nproc)"
bash fuzz/seed-corpus.sh build-fuzz/seeds
mkdir -p build-fuzz/findings
status=0
for t in "${targets[@]}"; do
  corpus=build-fuzz/corpus/$t
  mkdir -p "$corpus"
  # libFuzzer adds what it learns to the first folder; the seeds stay as they are
  # fuzz/regressions/<target>/: the inputs past runs found, each fixed; they run first, every time
  regressions=()
  [ -d fuzz/regressions/"$t" ] && regressions=(fuzz/regressions/"$t")
  if REFRAX_FUZZ_DATASET=$PWD/build-fuzz/seeds/dataset ./build-fuzz/fuzz_$t -runs="$runs" -max_len=131072 -timeout=20 -rss_limit_mb=4096 \
       -artifact_prefix=build-fuzz/findings/"$t"- "$corpus" build-fuzz/seeds/"$t" "${regressions[@]}" > build-fuzz/"$t".log 2>&1; then
    echo "fuzz $t: $(grep -o 'Done [0-9]* runs' build-fuzz/"$t".log | tail -n 1), no finding"
  else
    echo "fuzz $t: FINDING (build-fuzz/$t.log, build-fuzz/findings/)"
    tail -n 30 build-fuzz/"$t".log
    status=1
  fi
done
exit $status
