#!/usr/bin/env bash
# House rules that a compiler does not check, run by CTest (test "house") on every build.
#   1. Includes point one way, down the order of the top CMakeLists.txt: a file in a folder
#      includes only headers of its own folder or of folders listed before it (model, view,
#      image, section, bake, renderer, print, api, workers, server, cli). An include that
#      points up is a circle in the house.
#   2. JSON is written through jsonText (model/json_text.hpp) only: nlohmann's bare dump()
#      throws on text that is not UTF-8, and one such throw ended the server.
# Usage: bash scripts/check-house.sh   (from anywhere; exits 1 naming each breach)
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
order=(model view image section bake renderer print api workers server cli)
declare -A rank
for i in "${!order[@]}"; do rank[${order[$i]}]=$i; done

for folder in "${order[@]}"; do
    mine=${rank[$folder]}
    while IFS= read -r hit; do
        [ -n "$hit" ] || continue
        target=$(sed -E 's/.*#include "([a-z]+)\/.*/\1/' <<<"$hit")
        [ -n "${rank[$target]+x}" ] || continue  # not a geoslice folder (e.g. tests/)
        if [ "${rank[$target]}" -gt "$mine" ]; then
            echo "house: $folder/ includes $target/, which is above it: $hit"
            status=1
        fi
    done < <(git grep -nE '^#include "[a-z]+/' -- "$folder" || true)
done

product="${order[*]}"
if hits=$(git grep -nE '\.dump\(' -- $product | grep -v 'json-dump-ok'); then
    echo "house: a bare nlohmann dump() outside model/json_text.hpp (use jsonText, which cannot throw on text):"
    echo "$hits"
    status=1
fi
exit $status
