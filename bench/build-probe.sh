# Sourced by the bench scripts: builds ../shared/tools/rqprobe (read-only there) into
# build/rqprobe once, and sets $probe to its binary and $device to a file-name-safe name of
# device 0.
# A user's clone has no ../shared: then the benchmark runs without the probe's columns and
# says so.
shared=${REFRAX_SHARED:-../shared}
probe_dir=build/rqprobe
probe=""
if [ -x "$probe_dir/rqprobe" ]; then
  probe="$PWD/$probe_dir/rqprobe"
elif [ -d "$shared/tools/rqprobe" ]; then
  rm -rf "$probe_dir" && mkdir -p "$probe_dir"
  cp -r "$shared/tools/rqprobe/." "$probe_dir/"
  chmod -R u+w "$probe_dir"
  (cd "$probe_dir" && sh build.sh >/dev/null) && probe="$PWD/$probe_dir/rqprobe"
fi
[ -n "$probe" ] || echo "bench: no rqprobe ($shared/tools/rqprobe, or set REFRAX_SHARED): measuring without the probe's floor" >&2
device=$(./build/refrax devices | sed -n 's/^\[0\] \([^(]*\).*/\1/p' | tr -c 'A-Za-z0-9\n' '_' | sed 's/_*$//')
mkdir -p bench/results
