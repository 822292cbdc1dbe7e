#!/usr/bin/env bash
# Installs every Debian 12 package geoslice needs to build, test, benchmark and fuzz.
# Idempotent and non-interactive; README, .ci/run and deploy/Dockerfile all call it.
# Run as root (or with sudo available).
set -euo pipefail

packages=(
  # toolchain
  build-essential cmake ninja-build pkg-config git ca-certificates
  clang libclang-rt-14-dev            # libFuzzer targets and sanitizers under clang
  # headless GL: EGL (device + surfaceless), OSMesa, GL headers
  libegl-dev libgl-dev libopengl-dev libgles-dev libosmesa6-dev libegl-mesa0 libgl1-mesa-dri
  # maths and geometry
  libglm-dev libeigen3-dev libembree-dev libmeshoptimizer-dev
  # model formats
  libtinygltf-dev libdraco-dev libpugixml-dev nlohmann-json3-dev libstb-dev
  # images
  libopenimageio-dev libturbojpeg0-dev libjpeg62-turbo-dev libpng-dev libwebp-dev zlib1g-dev libzstd-dev
  # geodesy (GeographicLib) and PROJ as the test oracle (cs2cs)
  libgeographiclib-dev proj-bin
  # service and CLI
  libboost-dev libspdlog-dev libfmt-dev libcli11-dev curl   # Boost.Beast/Asio: the HTTP server
  libcpp-httplib-dev                  # the HTTP client of the tests and benchmarks
  # tests and benchmarks
  libgtest-dev libgmock-dev libbenchmark-dev
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: installed ${missing[*]}"
