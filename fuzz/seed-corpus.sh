#!/usr/bin/env bash
# The fuzz targets' seed corpus, made from the project's own outputs: a tiny synthetic dataset,
# a short training run (checkpoint, height field, PLY) and the interop samples, written by
# REFRAX (default build/refrax). Usage: fuzz/seed-corpus.sh OUT_DIR
set -euo pipefail
out=${1:?usage: fuzz/seed-corpus.sh OUT_DIR}
REFRAX=${REFRAX:-$(cd "$(dirname "$0")/.." && pwd)/build/refrax}
[ -x "$REFRAX" ] || { echo "seed-corpus: $REFRAX not found (build first, or set REFRAX)" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/refrax-seeds.XXXXXX")
trap 'rm -rf "$work"' EXIT
"$REFRAX" synth nerfrac-primary-sine --size tiny -o "$work/data" > /dev/null
"$REFRAX" train "$work/data" -o "$work/run" --steps 4 --gaussians 30 --patch 16 --mlp-width 16 --mlp-layers 1 \
  --checkpoint-every 4 --progress-every 100 > /dev/null 2>&1
mkdir -p "$work/samples"
"$REFRAX" interop-samples --output "$work/samples" --count 20 > /dev/null
rm -rf "$out"
for t in blender water_json npy ply gltf png checkpoint height_field; do mkdir -p "$out/$t"; done
cp "$work/data/transforms_train.json" "$out/blender/train.json"
cp "$work/data/transforms_test.json" "$out/blender/test.json"
cp "$work/data/water.json" "$out/water_json/synth.json"
printf '{"ior": 1.33, "height": -1.0, "depth": 2.0, "domain": [-1.0, -1.0, 1.0, 1.0], "frame": "loaded"}' > "$out/water_json/plain.json"
cp "$work/data/poses_bounds.npy" "$out/npy/poses_bounds.npy"
cp "$work/data/water_gt_height.npy" "$out/npy/height.npy"
cp "$work/run/point_cloud.ply" "$out/ply/run.ply"
for f in "$work/samples"/*.ply; do cp "$f" "$out/ply/"; done
# (the interop samples' 150-200 KB meshes would slow every execution: the synthesiser's 68 KB
# one, and one triangle written out here, stand for glTF)
cp "$work/data/water_gt.gltf" "$out/gltf/synth.gltf"
printf '%s' '{"asset":{"version":"2.0"},"scene":0,"scenes":[{"nodes":[0]}],"nodes":[{"mesh":0,"translation":[0,0,0.5]}],' \
  '"meshes":[{"primitives":[{"attributes":{"POSITION":0},"indices":1}]}],' \
  '"accessors":[{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":[0,0,0],"max":[1,1,0]},' \
  '{"bufferView":1,"componentType":5123,"count":3,"type":"SCALAR"}],' \
  '"bufferViews":[{"buffer":0,"byteOffset":0,"byteLength":36},{"buffer":0,"byteOffset":36,"byteLength":6}],' \
  '"buffers":[{"byteLength":42,"uri":"data:application/octet-stream;base64,AAAAAAAAAAAAAAAAAACAPwAAAAAAAAAAAAAAAAAAgD8AAAAAAAABAAIA"}]}' \
  > "$out/gltf/triangle.gltf"
cp "$work/data/train/$(ls "$work/data/train" | head -n 1)" "$out/png/view.png"
# the checkpoint and height field without their checksums (the targets append them)
ckpt=$(ls "$work/run/checkpoints"/*.ckpt | tail -n 1)
head -c -4 "$ckpt" > "$out/checkpoint/run.ckpt"
head -c -4 "$work/run/height_field.bin" > "$out/height_field/run.bin"
# the images the Blender target's seeds name
mkdir -p "$out/dataset"
cp -r "$work/data/train" "$work/data/test" "$out/dataset/"
echo "seed corpus in $out: $(find "$out" -type f | wc -l) files"
