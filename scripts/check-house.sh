#!/usr/bin/env bash
# House rules that a compiler does not check, run by CTest (test "house") on every build.
#   1. JSON is written through jsonText (model/json_text.hpp) only: nlohmann's bare dump()
#      throws on text that is not UTF-8, and one such throw ended the server.
# Usage: bash scripts/check-house.sh   (from anywhere; exits 1 naming each breach)
set -euo pipefail
cd "$(dirname "$0")/.."
status=0
product="model section bake renderer print api workers server cli"
if hits=$(git grep -nE '\.dump\(' -- $product | grep -v 'json-dump-ok'); then
    echo "house: a bare nlohmann dump() outside model/json_text.hpp (use jsonText, which cannot throw on text):"
    echo "$hits"
    status=1
fi
exit $status
