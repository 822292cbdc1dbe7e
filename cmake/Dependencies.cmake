# Every dependency comes from a Debian 12 package (scripts/install-deps.sh).
find_package(Threads REQUIRED)
find_package(glm REQUIRED)
find_package(Eigen3 REQUIRED NO_MODULE)
find_package(nlohmann_json 3 REQUIRED)
find_package(pugixml REQUIRED)
find_package(draco REQUIRED)
find_package(embree 3 REQUIRED)
find_package(CLI11 REQUIRED)
find_package(spdlog REQUIRED)
find_package(fmt REQUIRED)
find_package(zstd REQUIRED)  # libzstd-dev: the baked index texture's lossless encoding
find_package(PNG REQUIRED)   # libpng-dev
find_package(Boost 1.74 REQUIRED)  # libboost-dev: Beast/Asio (header-only), the HTTP transport
find_package(OpenSSL 3 REQUIRED COMPONENTS Crypto)  # libssl-dev: SHA-256 and constant-time compare of API keys
find_package(ZLIB REQUIRED)  # zlib1g-dev: gzip of JSON answers, zlib-compressed VTK .vtu data
# libxxhash-dev: XXH64, the baked package's file checksums (pkg-config only on Debian 12).
find_package(PkgConfig REQUIRED)
pkg_check_modules(XXHASH REQUIRED IMPORTED_TARGET libxxhash)
# libdxflib-dev: the DXF writer of section/fill/dxf_export (pkg-config only).
pkg_check_modules(DXFLIB REQUIRED IMPORTED_TARGET dxflib)
# libtinyobjloader-dev: the .mtl materials of OBJ models (model/io/obj).
pkg_check_modules(TINYOBJLOADER REQUIRED IMPORTED_TARGET tinyobjloader)

# GeographicLib ships only a find-module on Debian.
list(APPEND CMAKE_MODULE_PATH /usr/share/cmake/geographiclib)
find_package(GeographicLib REQUIRED)
add_library(geoslice_geographiclib INTERFACE)
target_include_directories(geoslice_geographiclib SYSTEM INTERFACE ${GeographicLib_INCLUDE_DIRS})
target_link_libraries(geoslice_geographiclib INTERFACE ${GeographicLib_LIBRARIES})

# PROJ (libproj-dev, 9.1): every CRS other than CGCS2000, from its local proj.db
# (proj-data); geoslice turns network access off in every context it makes.
find_package(PROJ 9 CONFIG REQUIRED)

# tinygltf: Debian's shared library is built without Draco, so model/ compiles the
# implementation from Debian's header once, with TINYGLTF_ENABLE_DRACO.
find_path(TINYGLTF_INCLUDE_DIR tiny_gltf.h REQUIRED)
find_path(STB_INCLUDE_DIR stb_image.h PATHS /usr/include/stb REQUIRED)

if(GEOSLICE_TESTS)
  find_package(GTest REQUIRED)
endif()
# cpp-httplib is only the HTTP client of the tests and benchmarks (the server speaks Beast).
# Debian's is a compiled library (built with OpenSSL, zlib and brotli); its pkg-config Cflags
# carry the matching CPPHTTPLIB_*_SUPPORT defines (one definition rule).
if(GEOSLICE_TESTS OR GEOSLICE_BENCH)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(HTTPLIB REQUIRED IMPORTED_TARGET cpp-httplib)
  add_library(geoslice_httplib INTERFACE)
  target_link_libraries(geoslice_httplib INTERFACE PkgConfig::HTTPLIB Threads::Threads)
endif()
