#!/usr/bin/env bash
# Fails when a tracked C++ file does not match the repository's .clang-format (the house
# format, STYLE.md rule 5). Run by ctest as the test `format` (labels format, unit), so
# scripts/test.sh and CI keep the tree formatted. Fix with:
#   git ls-files '*.cpp' '*.hpp' '*.h' | xargs clang-format -i
# Usage: bash scripts/check-format.sh [clang-format binary]
set -euo pipefail
cd "$(dirname "$0")/.."
clang_format=${1:-clang-format}
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  mapfile -t files < <(git ls-files '*.cpp' '*.hpp' '*.h' '*.cc')
else
  # A source tree without .git (an exported tarball): the C++ folders themselves.
  mapfile -t files < <(find api bake bench cli image model print renderer section server tests view workers \
    -type f \( -name '*.cpp' -o -name '*.hpp' -o -name '*.h' -o -name '*.cc' \) \
    -not -path '*/node_modules/*' -not -path 'tests/data/*' | sort)
fi
[ "${#files[@]}" -gt 0 ] || { echo "check-format: no C++ files found" >&2; exit 1; }
# One clang-format call for all files: --dry-run --Werror prints every mismatch as
# file:line and exits non-zero if any file differs.
existing=()
for f in "${files[@]}"; do [ -f "$f" ] && existing+=("$f"); done   # skip deleted-but-indexed
if ! "$clang_format" --dry-run --Werror "${existing[@]}"; then
  echo "check-format: files above do not match .clang-format; run clang-format -i on them" >&2
  exit 1
fi
echo "check-format: ${#existing[@]} C++ files match .clang-format"
