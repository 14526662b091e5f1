#!/usr/bin/env bash
# Formats the C++ sources with clang-format (.clang-format: deal.II's style, 100 columns).
#   bash tools/indent.sh          format in place
#   bash tools/indent.sh --check  exit 1 and list the files that are not formatted
set -euo pipefail
cd "$(dirname "$0")/.."
files=$(git ls-files '*.h' '*.cc')
if [ "${1:-}" = "--check" ]; then
  bad=0
  for f in $files; do
    if ! clang-format --style=file "$f" | cmp -s - "$f"; then
      echo "not formatted: $f"
      bad=1
    fi
  done
  exit $bad
fi
clang-format --style=file -i $files
