#!/usr/bin/env bash
# The installed CMake package works: `cmake --install` a build into a fresh
# prefix, then configure, build and run tests/consumer against it (find_package
# (warpmesh CONFIG), warpmesh::warpmesh), and check that the consumer, which
# uses no reader or writer, does not link libpng or libhdf5.  Registered with CTest
# (installed_package); also runnable by hand.
#
#   scripts/test-install.sh [BUILD_DIR]     (default: build/)
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${1:-${WARPMESH_BUILD_DIR:-$root/build}}"
tmp="$(mktemp -d)"
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
for h in "$tmp"/prefix/include/warpmesh/*.hpp; do
  # Public headers include only public headers.
  { grep -ho '#include "[^"]*"' "$h" || true; } | sed 's/#include "\(.*\)"/\1/' | while read -r inc; do
    [ -f "$tmp/prefix/include/$inc" ] || { echo "test-install: $(basename "$h") includes $inc, which is not installed" >&2; exit 1; }
  done
done
cmake -S "$root/tests/consumer" -B "$tmp/consumer" -DCMAKE_PREFIX_PATH="$tmp/prefix" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$tmp/consumer" >/dev/null
if grep -q 'png\|hdf5' "$tmp/consumer/CMakeFiles/consumer.dir/link.txt"; then
  echo "test-install: the consumer of warpmesh::warpmesh links libpng or libhdf5:" >&2
  cat "$tmp/consumer/CMakeFiles/consumer.dir/link.txt" >&2
  exit 1
fi
"$tmp/consumer/consumer"
# warpmesh::io from the installed package: the writers with HDF5 (found by
# the package config for the io component).
if [ -x "$tmp/consumer/consumer_io" ]; then
  mkdir "$tmp/out"
  "$tmp/consumer/consumer_io" "$tmp/out"
  for f in disc.xdmf disc.h5 disc_facets.xdmf disc_facets.h5; do
    [ -s "$tmp/out/$f" ] || { echo "test-install: consumer_io did not write $f" >&2; exit 1; }
  done
fi
echo "test-install: ok"
