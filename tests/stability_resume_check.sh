#!/usr/bin/env bash
# bench/stability.sh --resume keeps earlier rows only from the same settings and the same training
# code (run_info.txt's sizes= and code=). A changed model-size rule once slipped through under an
# unchanged settings text and nearly mixed two models in one chart; this checks the refusals,
# which come before any training: rows from other code, rows with no code recorded, rows from
# other settings. Each must exit 2, name the reason and leave the earlier rows as they were.
# Run from the source tree (CTest: tests/CMakeLists.txt), with REFRAX set to the binary.
set -u
fail() { echo "stability_resume_check: $*" >&2; exit 1; }
out=$(mktemp -d "${TMPDIR:-/tmp}/refrax-resume-check.XXXXXX")
trap 'rm -rf "$out"' EXIT
# The settings text that `--medium --steps 15` writes (bench/stability.sh, "sizes="): a short
# step count, so that a resume the checks wrongly let through fails fast instead of training
# for hours. If the script's text changes, the first case below says so.
sizes='nerfrac-primary-sine --size full --width 128 (128 x 128 px, 8 training views, 1 test view); 15 steps on whole images, model size derived from the data, SH degree 0, the settings of the full-size table (bench/presets.sh --cpu-full), restarts at steps 5,8 (step count set with --steps 15)'
rows='sweep,value,slope_bound,tilt_deg,ior,train_views,model,exit_code,failed,nan_count,psnr,ssim,surface_rmse,train_seconds,gaussians,run_seconds
slope,1,0.314,0,1.1,8,refrax,0,0,0,24.1,0.8,0.008,260,2000,270'

# expect NAME RUN_INFO MESSAGE: a resume over these rows exits 2 with MESSAGE, rows untouched
expect_refusal() {
  printf '%s\n' "$rows" >"$out/stability.csv"
  printf '%s\n' "$2" >"$out/run_info.txt"
  local log code
  log=$(timeout 60 bash bench/stability.sh --medium --steps 15 --resume --out "$out" 2>&1)
  code=$?
  [ $code = 2 ] || fail "$1: exit $code, expected 2 (a refusal before any training); output: $log"
  grep -qF -- "$3" <<<"$log" || fail "$1: the refusal does not say '$3'; it says: $log"
  [ "$(cat "$out/stability.csv")" = "$rows" ] || fail "$1: the earlier rows changed"
  [ "$(cat "$out/run_info.txt")" = "$2" ] || fail "$1: run_info.txt changed"
  echo "ok: $1"
}

expect_refusal "other settings" "$(printf 'seconds=10\nrows=1 of 37\nsizes=%s, other\ncode=0123abc' "$sizes")" \
  "were trained with other settings"
expect_refusal "other training code" "$(printf 'seconds=10\nrows=1 of 37\nsizes=%s\ncode=0123abc' "$sizes")" \
  "come from training code 0123abc"
expect_refusal "no training code recorded" "$(printf 'seconds=10\nrows=1 of 37\nsizes=%s' "$sizes")" \
  "come from training code not recorded"
