#!/usr/bin/env bash
# Installs what warpmesh needs from Debian packages, if missing.  Idempotent:
# a second run installs nothing and needs no network.
set -euo pipefail

need=()
have_pkg() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
for pkg in cmake g++ make libboost-dev libboost-test-dev libpng-dev zlib1g-dev libtiff-dev pkg-config python3; do
  have_pkg "$pkg" || need+=("$pkg")
done
# libgomp ships with g++ (OpenMP); Boost.Interval and Boost.Multiprecision are
# header-only parts of libboost-dev.

if ((${#need[@]})); then
  echo "setup: installing ${need[*]}"
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}"
else
  echo "setup: all dependencies present"
fi
