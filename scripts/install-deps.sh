#!/usr/bin/env bash
# Installs everything Refrax needs on a fresh Debian bookworm (run as root, or with sudo).
# Mesa's lavapipe with ray queries needs Mesa >= 24, which bookworm has only in
# bookworm-backports; the suite is added with the mirror URI this machine already uses.
set -euo pipefail
SUDO=""; [ "$(id -u)" = 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive

have_backports() {
  grep -rhsE '^\s*(Suites:.*|deb .*)bookworm-backports' /etc/apt/sources.list /etc/apt/sources.list.d/ >/dev/null
}

if ! have_backports; then
  # Reuse the URI that the existing sources give for plain 'bookworm'.
  uri=""
  if [ -f /etc/apt/sources.list.d/debian.sources ]; then
    uri=$(awk '/^URIs:/{u=$2} /^Suites:/ && / bookworm( |$)/{print u; exit}' /etc/apt/sources.list.d/debian.sources)
  fi
  if [ -z "$uri" ] && [ -f /etc/apt/sources.list ]; then
    uri=$(awk '$1=="deb" && $3=="bookworm"{print $2; exit}' /etc/apt/sources.list)
  fi
  if [ -z "$uri" ]; then
    echo "install-deps: cannot find an apt source for 'bookworm' to reuse for bookworm-backports" >&2
    exit 1
  fi
  echo "install-deps: adding bookworm-backports from $uri"
  printf 'Types: deb\nURIs: %s\nSuites: bookworm-backports\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' "$uri" \
    | $SUDO tee /etc/apt/sources.list.d/refrax-backports.sources >/dev/null
fi

$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  build-essential cmake pkg-config git \
  libvulkan-dev libvulkan-volk-dev vulkan-validationlayers glslang-tools spirv-tools vulkan-tools \
  libglm-dev libtinygltf-dev nlohmann-json3-dev libstb-dev libglfw3-dev libimgui-dev doctest-dev \
  xvfb xauth clang-14 libfuzzer-14-dev >/dev/null  # clang and libFuzzer: the loaders' fuzz targets (fuzz/)
# COLMAP (CPU build): structure from motion for scripts/colmap-check.sh, the CTest test that
# trains on poses COLMAP recovers from a synthetic dataset's images.
$SUDO apt-get install -y -qq --no-install-recommends colmap >/dev/null
# GDAL's tools: the tests read `refrax export --bottom`'s GeoTIFFs back with a reader that is
# not ours (gdalinfo, gdal_translate), as a GIS would.
$SUDO apt-get install -y -qq --no-install-recommends gdal-bin >/dev/null
# python3 and npm: scripts/interop-check.sh (the field's own tools are npm packages, its
# comparison is a Python script). Debian's nodejs and npm only where the machine has no npm:
# a newer node from elsewhere (with its own npm) is kept, and an older one is topped up by
# interop-check.sh with node from the npm registry.
$SUDO apt-get install -y -qq --no-install-recommends python3 >/dev/null
command -v npm >/dev/null 2>&1 || $SUDO apt-get install -y -qq --no-install-recommends nodejs npm >/dev/null
$SUDO apt-get install -y -qq --no-install-recommends -t bookworm-backports \
  mesa-vulkan-drivers >/dev/null
echo "install-deps: done ($(dpkg-query -W -f='${Version}' mesa-vulkan-drivers) mesa-vulkan-drivers)"
