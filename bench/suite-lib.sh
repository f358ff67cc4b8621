# Shared by the benchmark suites (bench/speed-accuracy.sh, bench/model-size.sh): options,
# the device line, datasets, training runs and their rows in the suite's CSVs. Sourced, not run.
#   --full       GPU-sized run: full-size presets, reference step counts
#   --smoke      a seconds-long run of the whole pipeline (1 preset, 2 configurations, ~20 steps)
#   --out DIR    report folder (default bench/results/<suite>/)
#   --keep-work  keep the datasets and run folders (in DIR/work/) instead of a temporary folder
#   --charts-only  no training: the charts and summary.md again from the CSVs in DIR (e.g. after
#                an interrupted run: its rows are appended run by run)
# REFRAX=path/to/refrax overrides the binary (default build/refrax).
set -euo pipefail

suite_root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
REFRAX=${REFRAX:-$suite_root/build/refrax}

suite_parse_args() {  # suite name, then the script's arguments
  suite=$1
  shift
  mode=default
  out=$suite_root/bench/results/$suite
  keep_work=0
  charts_only=0
  while [ $# -gt 0 ]; do
    case $1 in
      --full) mode=full ;;
      --smoke) mode=smoke ;;
      --out) [ $# -ge 2 ] || { echo "$suite: --out needs a folder" >&2; exit 2; }; out=$2; shift ;;
      --keep-work) keep_work=1 ;;
      --charts-only) charts_only=1 ;;
      -h|--help) sed -n '2,/^set -/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; exit 0 ;;
      *) echo "$suite: unknown option '$1' (--full, --smoke, --out DIR, --keep-work, --charts-only)" >&2; exit 2 ;;
    esac
    shift
  done
  . "$suite_root/bench/ensure-build.sh"
  ensure_refrax "$suite" "$REFRAX"
  mkdir -p "$out"
  out=$(cd "$out" && pwd)
  if [ $keep_work = 1 ]; then
    work=$out/work
    rm -rf "$work"
    mkdir -p "$work"
  else
    work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-$suite.XXXXXX")
    trap 'rm -rf "$work"' EXIT
  fi
  size=tiny
  [ $mode = full ] && size=full
  device=$("$REFRAX" devices | sed -n '1s/^\[[0-9]*\] //p')  # sed reads every line: no SIGPIPE under pipefail
  suite_start=$(date +%s)
  load_at_start=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown)
  echo "$suite (${suite_mode_label:-$mode}) on $device -> $out"  # a script's own mode (presets.sh --cpu-full) names itself
}

suite_dataset() {  # preset [synth options...] -> prints the dataset folder (made once)
  local preset=$1
  shift
  local key
  key=$(echo "$preset $size $*" | tr -c 'A-Za-z0-9.-' '_')
  local dir=$work/data/$key
  if [ ! -d "$dir" ]; then
    "$REFRAX" synth "$preset" --size "$size" -o "$dir" "$@" > "$work/synth-$key.log" 2>&1 ||
      { cat "$work/synth-$key.log" >&2; echo "$suite: synth $preset failed" >&2; exit 1; }
  fi
  echo "$dir"
}

# suite_train CSV SET dataset run-name [train options...]: trains into work/runs/NAME and
# appends its rows (one per evaluation) to CSV with the constant columns SET (k=v,...).
# A failed run is reported and skipped (its log kept in work/), not fatal: a suite is many runs.
suite_train() {
  local csv=$1 set=$2 data=$3 name=$4
  shift 4
  local run=$work/runs/$name
  mkdir -p "$work/runs"
  local t0
  t0=$(date +%s)
  if "$REFRAX" train "$data" -o "$run" --recipe reference --checkpoint-every 0 --progress-every 100000 "$@" > "$work/runs/$name.log" 2>&1; then
    "$REFRAX" report "$run" -o "$csv" --append --evaluations --set "$set" > /dev/null
    echo "  $name: $(tail -n 1 "$work/runs/$name.log") [$(( $(date +%s) - t0 )) s wall]"
  else
    echo "  $name: FAILED ($(tail -n 1 "$work/runs/$name.log"))" | tee -a "$out/failures.txt"
  fi
}

# suite_warmup dataset [train options...]: a 4-step run through every stage the options use
# (surface unfrozen, face then smooth normals, an evaluation), discarded. Lavapipe compiles
# each pipeline at its first dispatch (up to minutes for the largest MLP kernels) and Mesa's
# disk cache keeps them: warming up first keeps compile time out of the measured runs.
suite_warmup() {
  local data=$1
  shift
  local dir=$work/warmup
  rm -rf "$dir"
  # A run's restarts (at a third of its steps and later) lie past these 4 steps, which train
  # refuses: the warm-up restarts at step 2 instead (the last --restart-gaussians counts).
  local restart=()
  case " $* " in *" --restart-gaussians "*) restart=(--restart-gaussians 2) ;; esac
  "$REFRAX" train "$data" -o "$dir" --recipe reference "$@" --steps 4 --surface-freeze 0 --face-normals-until 2 --eval-every 2 \
    --checkpoint-every 0 --progress-every 100000 ${restart[@]+"${restart[@]}"} > "$work/warmup.log" 2>&1 ||
    echo "  warm-up failed (the run will say why): $(tail -n 1 "$work/warmup.log")" >&2
  rm -rf "$dir"
}

# suite_step_seconds dataset [train options...]: training seconds per step of these options,
# after suite_warmup, from an 8-step run (surface unfrozen: every stage of a step is timed):
# the time between its evaluations at steps 2 and 8, so the first steps' one-off costs
# (pipelines loaded on first dispatch, buffers allocated) stay out.
suite_step_seconds() {
  local data=$1
  shift
  suite_warmup "$data" "$@"
  local dir=$work/timing
  rm -rf "$dir" "$work/timing.csv"
  "$REFRAX" train "$data" -o "$dir" --recipe reference "$@" --steps 8 --eval-every 2 --surface-freeze 0 --checkpoint-every 0 --progress-every 100000 > "$work/timing.log" 2>&1 &&
    "$REFRAX" report "$dir" -o "$work/timing.csv" --evaluations > /dev/null &&
    awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) { if ($i == "eval_step") a = i; if ($i == "eval_seconds") b = i }; next }
      $a == 2 { s0 = $b } $a == 8 { s1 = $b } END { printf "%.4f\n", (s1 - s0) / 6 }' "$work/timing.csv" ||
    echo 0  # a failing configuration fails again in its run, and is reported there
  rm -rf "$dir"
}

suite_chart() {  # chart options...: refrax chart, stopping the suite on an error
  "$REFRAX" chart "$@" > /dev/null
}

# A markdown table of CSV columns: suite_table CSV "col1 col2 ..." [awk filter on $row]
# Rows whose eval_step differs from config_steps (intermediate evaluations) are left out.
suite_table() {
  local csv=$1 cols=$2
  awk -F, -v cols="$cols" '
    NR == 1 { for (i = 1; i <= NF; i++) idx[$i] = i; n = split(cols, c, " ");
              line = "|"; sep = "|"; for (k = 1; k <= n; k++) { line = line " " c[k] " |"; sep = sep " --- |" }
              print line; print sep; next }
    ("eval_step" in idx) && $idx["eval_step"] != $idx["config_steps"] { next }
    { line = "|"; for (k = 1; k <= n; k++) { v = (c[k] in idx) ? $idx[c[k]] : "";
        if (v ~ /^-?[0-9]+\.[0-9]+(e-?[0-9]+)?$/) v = sprintf(((v + 0 < 0.1 && v + 0 > -0.1) ? "%.4g" : "%.2f"), v);
        line = line " " v " |" } print line }' "$csv"
}

# The machine's load: a shared machine's timings need it said.
suite_load_line() {
  echo "Load average (1, 5, 15 min) at the start: $load_at_start; at the end: $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo unknown) ($(nproc) cores)."
}

suite_elapsed() { echo $(( $(date +%s) - suite_start )); }

# The end of a suite's summary.md: its failed runs (suite_train's failures.txt), if any.
suite_failed_runs() {
  [ -f "$out/failures.txt" ] || return 0
  echo "## Failed runs"
  echo
  sed 's/^ */- /' "$out/failures.txt"
}

# summary.md.tmp, written whole, becomes summary.md (never half a summary).
suite_publish_summary() {
  mv "$out/summary.md.tmp" "$out/summary.md"
  echo "$suite: done in $(suite_elapsed) s -> $out/summary.md"
}
