# Sourced by the bench suites so that each is one command from a fresh clone: when the
# default binary (build/refrax) is missing, install what is missing and build it, as
# scripts/demo.sh does. A REFRAX=path override is never built, only checked.
ensure_refrax() {  # $1: the suite's name, $2: the refrax binary it will run
  local root
  root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  if [ ! -x "$2" ] && { [ "$2" = "$root/build/refrax" ] || [ "$2" = "./build/refrax" ]; }; then
    echo "$1: no build yet: installing what is missing and building build/refrax" >&2
    (cd "$root" && { [ "${REFRAX_SKIP_INSTALL:-0}" = 1 ] || bash scripts/install-deps.sh; } &&
      cmake -S . -B build -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null && cmake --build build -j"$(nproc)") || exit 2
  fi
  [ -x "$2" ] || { echo "$1: $2 not found (build first, or set REFRAX=path)" >&2; exit 2; }
}
