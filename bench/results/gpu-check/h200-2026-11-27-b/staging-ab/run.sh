#!/bin/bash
# One device call: the host-transfer A/B (old bundle vs new, same data, same machine), then
# the new bundle's gpu-check (its own EGL fallback exercised: no VK_DRIVER_FILES given).
set -u
here=$(cd "$(dirname "$0")" && pwd)
for b in old new; do mkdir -p /tmp/$b && tar xJf "$here/$b.tar.xz" -C /tmp/$b || exit 3; done
printf '{"file_format_version":"1.0.1","ICD":{"library_path":"libEGL_nvidia.so.0","api_version":"1.4.312"}}\n' > /tmp/icd.json
ab() { local b=$1; shift; LD_LIBRARY_PATH=/tmp/$b/bundle/lib:${LD_LIBRARY_PATH:-} REFRAX_SOURCE_DIR=/tmp/$b/bundle VK_DRIVER_FILES=/tmp/icd.json VK_ICD_FILENAMES=/tmp/icd.json MESA_SHADER_CACHE_DIR=/tmp/cache /tmp/$b/bundle/bin/refrax "$@"; }
ab new synth nerfrac-primary-sine --size full -o /tmp/d > $OUT/ab-synth.log 2>&1
for round in 1 2; do
  for b in old new; do
    ab $b train /tmp/d -o /tmp/r$b$round --steps 200 --no-densify --profile --checkpoint-every 0 --progress-every 1000 > $OUT/ab-$b$round.log 2>&1
    echo "$b round $round: $(grep '^profile:' $OUT/ab-$b$round.log)" | tee -a $OUT/ab.txt
  done
done
grep -A5 "^profile:" $OUT/ab-old2.log $OUT/ab-new2.log
timeout 290 /tmp/new/bundle/gpu-check.sh --out /tmp/gc --train-minutes 1 --tests-minutes 2
cd /tmp/gc && cp summary.txt $OUT/ && find . -maxdepth 3 \( -name '*.log' -o -name '*.txt' -o -name '*.json' \) -size -4M | tar czf $OUT/gc.tgz -T -
cat summary.txt
