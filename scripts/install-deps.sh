#!/usr/bin/env bash
# The Debian 12 packages geoslice needs, in three lists, installed idempotently and
# non-interactively. README, .ci/run and deploy/Dockerfile all call this file, so they
# stay in step.
#   bash scripts/install-deps.sh            everything: build, tests, benchmarks, fuzzing, deploy tests
#   bash scripts/install-deps.sh --build    what compiling the geoslice binary needs (the image's build stage)
#   bash scripts/install-deps.sh --runtime  what running the binary needs (the image's runtime stage):
#                                           shared libraries, Mesa's EGL/OSMesa/llvmpipe, curl for health checks
#   add --list to print the packages instead of installing them.
# tests/deploy/runtime_deps_test.sh checks that every shared library the built binary
# loads comes from a package on the runtime list. Run as root (or with sudo available).
set -euo pipefail

build=(
  # toolchain
  build-essential cmake ninja-build pkg-config ccache ca-certificates
  # headless GL: EGL (device + surfaceless), OSMesa, GL headers
  libegl-dev libgl-dev libopengl-dev libgles-dev libosmesa6-dev
  # maths and geometry
  libglm-dev libeigen3-dev libembree-dev libmeshoptimizer-dev
  # model formats
  libtinygltf-dev libdraco-dev libpugixml-dev nlohmann-json3-dev libstb-dev
  # images
  libturbojpeg0-dev libjpeg62-turbo-dev libpng-dev libwebp-dev zlib1g-dev libzstd-dev
  libssl-dev                          # OpenSSL libcrypto: SHA-256 and constant-time compare of API keys
  libxxhash-dev                       # XXH64 checksums of the baked package's files
  libdxflib-dev                       # dxflib: the DXF export of sections
  libtinyobjloader-dev                # tinyobjloader: OBJ .mtl materials
  # geodesy: GeographicLib (CGCS2000), PROJ for every other CRS (library + its EPSG
  # database and grids in proj-data)
  libgeographiclib-dev libproj-dev proj-data
  # service and CLI
  libboost-dev libspdlog-dev libfmt-dev libcli11-dev   # Boost.Beast/Asio: the HTTP server
  libjs-leaflet                       # the web client embeds Debian's Leaflet (configure needs it)
  # print sheets (print/): PDF, raster and text layout through cairo; the sheet's font
  libcairo2-dev fonts-dejavu-core fonts-wqy-microhei   # DejaVu Sans; WenQuanYi for CJK unit names
)
# Everything else a developer or CI machine needs on top of the build list.
dev=(
  git curl
  clang libclang-rt-14-dev            # libFuzzer targets and sanitizers under clang
  clang-format                        # the house format, checked by ctest's test `format`
  libegl-mesa0 libgl1-mesa-dri        # llvmpipe for the GL tests
  proj-bin                            # PROJ's cs2cs as the CRS test oracle
  libgtest-dev libgmock-dev
  libcpp-httplib-dev                  # the HTTP client of the tests and benchmarks
  # bench/table1: its peers and plots (benchmark-only, never linked into geoslice):
  # VTK 9.1's cutters through Python, CGAL's Polygon_mesh_slicer (headers), matplotlib
  python3-vtk9 libcgal-dev python3-matplotlib
  # generators of the STL/PLY/DXF test files (tests/data/wire/make_*.py; the files are committed)
  python3-ezdxf python3-meshio
  # deploy tests (tests/deploy, deploy/test-image.sh): containers, load balancer, load
  podman buildah crun fuse-overlayfs debootstrap nginx-light wrk python3-yaml
  # web client tests (tests/web): the browser driven by playwright-core, CJK glyphs
  chromium fonts-wqy-microhei
  poppler-utils                       # pdftoppm/pdftotext open the print sheets' PDFs in tests
  prometheus                          # promtool checks /metrics in the server tests (no daemon is started)
  gdal-bin                            # ogrinfo/ogr2ogr read the GeoJSON sections back in the tests
)
# tests/web need Node.js with npm; one already there (e.g. NodeSource's, which bundles npm)
# is kept, since Debian's npm package conflicts with it.
command -v npm >/dev/null 2>&1 || dev+=(nodejs npm)
runtime=(
  libc6 libgcc-s1 libstdc++6 zlib1g
  libspdlog1.10 libfmt9
  libembree3-3 libtbb12 libmeshoptimizer2d libdraco7 libpugixml1v5 libgeographiclib23
  libproj25 proj-data                 # PROJ and its database (proj.db) and grids, and what libproj25
  # loads: sqlite (proj.db), tiff (grids), curl and its TLS/auth stack (PROJ's network
  # access, which geoslice switches off but the library links)
  libsqlite3-0 libtiff6 libdeflate0 libjbig0 liblerc4 liblzma5
  libcurl3-gnutls libbrotli1 libnghttp2-14 libidn2-0 libunistring2 librtmp1 libssh2-1 libpsl5
  libgnutls30 libnettle8 libhogweed6 libgmp10 libp11-kit0 libffi8 libtasn1-6 libssl3
  libgssapi-krb5-2 libkrb5-3 libk5crypto3 libkrb5support0 libcom-err2 libkeyutils1
  libldap-2.5-0 libsasl2-2
  libjpeg62-turbo libpng16-16 libwebp7 libzstd1 libxxhash0   # codecs (libjpeg also for libtiff)
  libdxflib3                          # DXF export
  libtinyobjloader2rc10               # OBJ .mtl materials
  # GL through glvnd: Mesa's EGL (device + surfaceless) and llvmpipe, OSMesa (dlopen)
  libegl1 libglvnd0 libegl-mesa0 libgl1-mesa-dri libosmesa6
  # print sheets: cairo and what it loads (pixman, fontconfig + FreeType, its X11/xcb
  # surface libraries, which libcairo2 links though geoslice draws headless), the font
  libcairo2 libpixman-1-0 libfontconfig1 fontconfig-config libfreetype6 libexpat1
  libxcb1 libxcb-shm0 libxcb-render0 libxrender1 libx11-6 libxext6 libxau6 libxdmcp6 libbsd0 libmd0
  fonts-dejavu-core fonts-wqy-microhei
  curl                                # HEALTHCHECK
)

role=all list=0
for a in "$@"; do
  case "$a" in
    --build) role=build ;;
    --runtime) role=runtime ;;
    --list) list=1 ;;
    -h|--help) sed -n 2,12p "$0"; exit 0 ;;
    *) echo "install-deps: unknown option '$a' (--build, --runtime, --list)" >&2; exit 2 ;;
  esac
done
case "$role" in
  build) packages=("${build[@]}") ;;
  runtime) packages=("${runtime[@]}") ;;
  all) packages=("${build[@]}" "${dev[@]}") ;;
esac
if [ "$list" -eq 1 ]; then
  printf '%s\n' "${packages[@]}"
  exit 0
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present ($role)"
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
echo "install-deps: installed ${missing[*]}"
