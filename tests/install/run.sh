#!/bin/sh
# Installs a laserfit build into a fresh prefix, then configures, builds and runs the out-of-tree
# consumer (tests/install/consumer) against it. The consumer's configure is told that
# OpenCASCADE, assimp, CGAL and Embree do not exist: the registration component must not need them
# (VTK it gets through PCL: Debian's libpcl-dev depends on libvtk9-dev).
#   tests/install/run.sh <build dir> <work dir>
set -eu
build=$1 work=$2
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work"
cmake --install "$build" --prefix "$work/prefix" > "$work/install.log"
cmake -S "$here/consumer" -B "$work/consumer" -DCMAKE_PREFIX_PATH="$work/prefix" \
  -DCMAKE_BUILD_TYPE=Release -DCMAKE_DISABLE_FIND_PACKAGE_OpenCASCADE=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_assimp=ON -DCMAKE_DISABLE_FIND_PACKAGE_CGAL=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_embree=ON > "$work/configure.log"
cmake --build "$work/consumer" > "$work/build.log"
"$work/consumer/consumer"
# The Python module, when built, imports from the prefix alone (no build tree on the path).
for dir in "$work"/prefix/lib/python3*/dist-packages; do
  [ -d "$dir/laserfit" ] || continue
  (cd "$work" && PYTHONPATH="$dir" /usr/bin/python3 -c \
    'import laserfit, sys; assert laserfit.__file__.startswith(sys.argv[1]), laserfit.__file__; print("import laserfit:", laserfit.__version__)' "$dir")
done
