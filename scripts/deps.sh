#!/usr/bin/env bash
# deps.sh: install the Debian packages bsfit needs, only those missing.
#   scripts/deps.sh          build + run dependencies
#   scripts/deps.sh --test   also what the tests use
set -euo pipefail

pkgs=(build-essential cmake pkg-config lua5.4 liblua5.4-dev liblapacke-dev libopenblas-dev)
if [ "${1:-}" = "--test" ]; then
  # clang, libclang-rt-14-dev: the libFuzzer targets (tests/fuzz, scripts/fuzz.sh);
  # luarocks: the rockspec test; man-db, groff-base: the man page test;
  # g++ and OpenCASCADE, python3-ezdxf: the CAD exchange readers; librsvg2-bin (rsvg-convert):
  # the pictures test; parallel (GNU parallel) and bsdutils (script): the batch test
  pkgs+=(libcmocka-dev python3-scipy luarocks man-db groff-base g++ libocct-data-exchange-dev
         libocct-foundation-dev libocct-modeling-data-dev python3-ezdxf librsvg2-bin parallel bsdutils
         clang libclang-rt-14-dev)
fi

missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "deps: installing ${missing[*]}" >&2
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
export DEBIAN_FRONTEND=noninteractive
$sudo apt-get update -qq
$sudo apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
