#!/usr/bin/env bash
# bench/stability.sh --resume keeps earlier rows only from the same settings and the same training
# code (run_info.txt's sizes= and code=). A changed model-size rule once slipped through under an
# unchanged settings text and nearly mixed two models in one chart; this checks the refusals,
# which come before any training: rows from other code, rows with no code recorded, rows from
# other settings. Each must exit 2, name the reason and leave the earlier rows as they were.
# Then the positive case, so that a script that refuses every resume fails: rows from these
# settings and this checkout's code, every row but the dry control's, must be kept as they
# were, the missing one trained (15 steps, seconds), and run_info.txt say all rows are done.
# It needs a checkout without local changes to the training code (else the script rightly
# refuses, its code being unknown): with them, it exits 77, which CTest reports as skipped.
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

# ---- the positive case: these settings, this checkout's code (as bench/stability.sh hashes it)
code_paths=(engine shaders trainer CMakeLists.txt)
if [ -n "$(git status --porcelain -- "${code_paths[@]}")" ]; then
  echo "stability_resume_check: the resume that must succeed is not run: local changes in ${code_paths[*]} (a resume refuses them)" >&2
  exit 77
fi
code=$(git ls-tree HEAD "${code_paths[@]}" | git hash-object --stdin)
# Every row of --medium but the dry control's, each with fields of its own after the first 7
# (the ones a resume keeps). The settings at amplitude x1 with 8 views are one run, shared by
# slope 1, tilt 0, ior 1.1 and views 8: their rows hold the same fields.
kept='sweep,value,slope_bound,tilt_deg,ior,train_views,model,exit_code,failed,nan_count,psnr,ssim,surface_rmse,train_seconds,gaussians,run_seconds'
n=0
for sv in slope:0.25 slope:0.5 slope:1 slope:1.6 slope:2.4 tilt:0 tilt:20 tilt:40 tilt:60 ior:1.1 ior:1.2 ior:1.33 ior:1.5 views:8 views:4 views:2; do
  for model in refrax flat-water no-refraction; do
    n=$((n + 1))
    psnr=$n
    case $sv in slope:1|tilt:0|ior:1.1|views:8) psnr=shared-$model ;; esac
    kept="$kept
${sv%%:*},${sv#*:},0,0,1.1,8,$model,0,0,0,$psnr,0.5,0.01,9,2000,10"
  done
done
printf '%s\n' "$kept" >"$out/stability.csv"
printf 'seconds=10\nrows=%d of 49\nsizes=%s\ncode=%s\n' "$n" "$sizes" "$code" >"$out/run_info.txt"
log=$(timeout 240 bash bench/stability.sh --medium --steps 15 --resume --out "$out" 2>&1)
code_rc=$?
[ $code_rc = 0 ] || fail "a resume of rows from these settings and this code: exit $code_rc, expected 0; output: $log"
trained=$(grep -cE '^[0-9:]+ [^ ]+: exit ' <<<"$log")
[ "$trained" = 1 ] || fail "a resume with one row missing trained $trained runs, expected 1; output: $log"
grep -qE '^[0-9:]+ [^ ]+no-refraction: exit 0,' <<<"$log" || fail "the missing row (the dry control, no-refraction) was not the one trained: $log"
# every kept row's kept fields as they were, the dry row trained, 49 rows
python3 - "$out/stability.csv" <<'PY' || fail "the rows after the resume: see above"
import csv, sys
rows = list(csv.DictReader(open(sys.argv[1])))
bad = []
if len(rows) != 49: bad.append('%d rows, expected 49' % len(rows))
n = 0
for sweep, values in [('slope', ['0.25', '0.5', '1', '1.6', '2.4']), ('tilt', ['0', '20', '40', '60']), ('ior', ['1.1', '1.2', '1.33', '1.5']), ('views', ['8', '4', '2'])]:
    for v in values:
        for model in ['refrax', 'flat-water', 'no-refraction']:
            n += 1
            want = 'shared-' + model if (sweep, v) in [('slope', '1'), ('tilt', '0'), ('ior', '1.1'), ('views', '8')] else str(n)
            got = [r for r in rows if r['sweep'] == sweep and r['value'] == v and r['model'] == model]
            if len(got) != 1 or got[0]['psnr'] != want or got[0]['run_seconds'] != '10':
                bad.append('%s %s %s: %s, expected psnr %s kept' % (sweep, v, model, got, want))
dry = [r for r in rows if r['sweep'] == 'dry']
if len(dry) != 1 or dry[0]['model'] != 'no-refraction' or dry[0]['exit_code'] != '0' or not dry[0]['psnr']:
    bad.append('the dry row: %s' % dry)
if bad:
    print('\n'.join(bad[:5]), file=sys.stderr)
    sys.exit(1)
PY
grep -qx 'rows=49 of 49' "$out/run_info.txt" || fail "run_info.txt after the resume: $(cat "$out/run_info.txt")"
grep -qx "code=$code" "$out/run_info.txt" || fail "run_info.txt does not record this checkout's code: $(cat "$out/run_info.txt")"
echo "ok: a resume of these settings and code keeps its rows and trains the missing one"
