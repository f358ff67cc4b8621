#!/usr/bin/env bash
# Installs what is missing, builds, and runs the whole test suite on lavapipe (or the device
# named by REFRAX_DEVICE) with the Khronos validation layer on.
#   scripts/test.sh              release build in build/
#   scripts/test.sh --sanitize   ASan+UBSan build in build-sanitize/
#   ... --build-only             build, run nothing (.ci/run builds the sanitizer suite beside the release one)
set -euo pipefail
cd "$(dirname "$0")/.."
build=build
cmake_args=(-DCMAKE_BUILD_TYPE=RelWithDebInfo)
ctest_args=()
sanitize=0
build_only=0
for arg in "$@"; do
  case $arg in
    --sanitize) sanitize=1 ;;
    --build-only) build_only=1 ;;
    *) echo "test.sh: unknown option '$arg' (--sanitize, --build-only)" >&2; exit 2 ;;
  esac
done
if [ $sanitize = 1 ]; then
  build=build-sanitize
  # Tests in the doctest suite "long" train for minutes; under ASan they would take several
  # times that and check no code path the short ones miss, so the release run alone has them
  # (and the second pass on the compute trace backend, the cases named "compute:..."), and so
  # has the end-to-end COLMAP check (label "colmap", scripts/colmap-check.sh).
  # And the cases listed in tests/sanitizer_pass_leaves_out.txt (long trainings and renders that
  # drive the host code the kept cases drive; the release pass runs them).
  ctest_args+=(-LE "long|colmap")  # the compute backend's pass runs in the release build
  # -O1 (ASan's documented level for reasonable speed) and line tables only (-g1, so reports
  # keep file and line): the instrumented test files compile in about half the time of -O2 -g
  # (test_train.cpp 67 s -> 35 s here), and CI's whole run had reached 70 minutes.
  cmake_args+=(-DREFRAX_SANITIZE=ON "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG" "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O1 -g1 -DNDEBUG")
  # Mesa's LLVM JIT keeps allocations for the process lifetime; leaks are not ours to judge.
  export ASAN_OPTIONS=detect_leaks=0:abort_on_error=1
  export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
fi
[ "${REFRAX_SKIP_INSTALL:-0}" = 1 ] || bash scripts/install-deps.sh
# Lavapipe compiles every pipeline at its first dispatch (seconds to minutes for the MLP
# kernels) and Mesa's disk cache keeps them for the next test process. Its default place is
# under $HOME, which a CI user may not be able to write: without it each test recompiles
# (here 15 s instead of 0.25 s for one surface test, 74 s instead of 6 s for a viewer test).
export MESA_SHADER_CACHE_DIR=${MESA_SHADER_CACHE_DIR:-$PWD/.cache/mesa-shader-cache}
mkdir -p "$MESA_SHADER_CACHE_DIR"
echo "test.sh: Mesa shader cache in $MESA_SHADER_CACHE_DIR${MESA_SHADER_CACHE_DISABLE:+ (disabled: MESA_SHADER_CACHE_DISABLE=$MESA_SHADER_CACHE_DISABLE)}"
# Each part prints its time ("test.sh: ... took N s"): CI's log then says where its hour goes.
timed() {
  local name=$1 start=$SECONDS rc=0
  shift
  "$@" || rc=$?
  echo "test.sh: $name took $((SECONDS - start)) s"
  return $rc
}
cmake -S . -B "$build" "${cmake_args[@]}" >/dev/null
timed "the $build build" cmake --build "$build" -j"$(nproc)"
[ $build_only = 0 ] || exit 0
cd "$build"
escape() { sed 's/[][\.*^$()+?{}|]/\\&/g'; }
if [ ${#ctest_args[@]} -gt 0 ]; then
  # Every line of the list must name a test: a renamed case fails here instead of slipping back.
  ctest -N | sed -n 's/^ *Test *#[0-9]*: //p' > sanitizer-all-tests.txt
  left_out=$(grep -v '^#' ../tests/sanitizer_pass_leaves_out.txt | grep -v '^$' || true)
  while IFS= read -r name; do
    grep -qxF -- "$name" sanitizer-all-tests.txt || { echo "test.sh: tests/sanitizer_pass_leaves_out.txt names no test: $name" >&2; exit 1; }
  done <<< "$left_out"
  left_out_re=$(escape <<< "$left_out" | paste -sd'|')
  timed "the sanitizer suite" ctest --output-on-failure -j"$(nproc)" "${ctest_args[@]}" -E "^compute:|^(${left_out_re:-none})\$"
else
  # The "long" training tests run after the rest, one at a time: lavapipe spreads each over
  # every core, and beside other tests one took over its 20-minute limit in CI (alone, 5 min here).
  # The compute trace backend's pass ("compute:" cases) leaves out the cases in the doctest
  # suite "one-backend": options, checkpoints and loaders whose behaviour no trace decides; and
  # those in "rayquery-only": acceleration structures' own cases (refit), which the compute
  # backend has none of, and the two backends' side-by-side comparison, which makes its own
  # context per backend (the first pass runs it). A rayquery-only case run there fails saying
  # so, rather than passing having checked nothing. (By name: CTest's labels come from a
  # doctest filter, which splits names at commas.)
  names_in() { ./tests/refrax_tests --list-test-cases --test-suite="$1" | grep -v '^\[doctest\]\|^===' | escape | paste -sd'|'; }
  one_backend=$(names_in one-backend)
  rayquery_only=$(names_in rayquery-only)
  status=0
  timed "the first pass" ctest --output-on-failure -j"$(nproc)" -LE long -E "^compute:" || status=$?
  timed "the compute-backend pass" ctest --output-on-failure -j"$(nproc)" -R "^compute:" \
    -E "^compute:(${one_backend:-none}|${rayquery_only:-none})\$" -LE long || status=$?
  # The long test runs once: it asserts the median and the worst of three seeds
  # (tests/test_train.cpp), so one seed's bad run is logged, not retried until it passes.
  # Verbose, so the log keeps every seed's figures (doctest's MESSAGE and WARN lines) on a pass too.
  timed "the long test" ctest --output-on-failure --verbose -L long -E "^compute:" || status=$?
  exit $status
fi
