#!/usr/bin/env bash
# The project's two commands (README.md):
#   bash tools/setup.sh run    install what is missing, build in Release, run prm/brick_contact.prm
#   bash tools/setup.sh test   install what is missing, build in Release, run the test suite
# The build goes to build/ (override with BUILD_DIR=...).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
mode=${1:-run}
build=${BUILD_DIR:-$here/build}

bash "$here/tools/install_dependencies.sh"

cmake -S "$here" -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build "$build" -j "$(nproc)"

# Open MPI refuses root unless told; sessions and CI run as root.
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
case "$mode" in
  run)
    cd "$build"
    ./feticontact "$here/prm/brick_contact.prm"
    echo "Output in $build/output/brick_contact: open solution.pvd and contact_surface.pvd in ParaView."
    ;;
  test)
    cd "$build"
    ctest --output-on-failure -j "$(nproc)"
    ;;
  *)
    echo "usage: $0 run|test" >&2
    exit 1
    ;;
esac
