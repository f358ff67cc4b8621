# Sourced by the bench scripts: builds ../shared/tools/rqprobe (read-only there) into
# build/rqprobe once, and sets $probe to its binary and $device to a file-name-safe name of
# device 0.
shared=${REFRAX_SHARED:-../shared}
probe_dir=build/rqprobe
if [ ! -x "$probe_dir/rqprobe" ]; then
  rm -rf "$probe_dir" && mkdir -p "$probe_dir"
  cp -r "$shared/tools/rqprobe/." "$probe_dir/"
  chmod -R u+w "$probe_dir"
  (cd "$probe_dir" && sh build.sh >/dev/null)
fi
probe="$PWD/$probe_dir/rqprobe"
device=$(./build/refrax devices | sed -n 's/^\[0\] \([^(]*\).*/\1/p' | tr -c 'A-Za-z0-9\n' '_' | sed 's/_*$//')
mkdir -p bench/results
