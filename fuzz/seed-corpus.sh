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
for t in blender water_json npy ply gltf png checkpoint height_field colmap; do mkdir -p "$out/$t"; done
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
# COLMAP: the first byte chooses the file (fuzz/fuzz_colmap.cpp); one PINHOLE camera, one image,
# one point, in text and in binary (little-endian: counts u64, ids u32, values f64)
printf '\x00# a comment\n1 PINHOLE 64 48 50 50 32 24\n2 SIMPLE_PINHOLE 64 48 50 32 24\n' > "$out/colmap/cameras.txt"
printf '\x011 1 0 0 0 0.5 -0.25 1 1 a b.png\n10 20 -1 11 21 1\n' > "$out/colmap/images.txt"
printf '\x021 0 0 -1 128 64 255 0.5 1 0 2 3\n' > "$out/colmap/points3D.txt"
f64_0='\x00\x00\x00\x00\x00\x00\x00\x00'
printf '\x03\x01\x00\x00\x00\x00\x00\x00\x00''\x01\x00\x00\x00''\x01\x00\x00\x00''\x40\x00\x00\x00\x00\x00\x00\x00''\x30\x00\x00\x00\x00\x00\x00\x00'\
'\x00\x00\x00\x00\x00\x00\x49\x40''\x00\x00\x00\x00\x00\x00\x49\x40''\x00\x00\x00\x00\x00\x00\x40\x40''\x00\x00\x00\x00\x00\x00\x38\x40' > "$out/colmap/cameras.bin"
printf '\x04\x01\x00\x00\x00\x00\x00\x00\x00''\x01\x00\x00\x00''\x00\x00\x00\x00\x00\x00\xf0\x3f'"$f64_0$f64_0$f64_0$f64_0$f64_0$f64_0"\
'\x01\x00\x00\x00''a.png\x00''\x00\x00\x00\x00\x00\x00\x00\x00' > "$out/colmap/images.bin"
printf '\x05\x01\x00\x00\x00\x00\x00\x00\x00''\x01\x00\x00\x00\x00\x00\x00\x00'"$f64_0$f64_0"'\x00\x00\x00\x00\x00\x00\xf0\xbf''\x80\x40\xff'\
'\x00\x00\x00\x00\x00\x00\xe0\x3f''\x00\x00\x00\x00\x00\x00\x00\x00' > "$out/colmap/points3D.bin"
