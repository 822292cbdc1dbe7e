# geoslice_warnings: every project target links this interface target.
add_library(geoslice_warnings INTERFACE)
target_compile_options(geoslice_warnings INTERFACE -Wall -Wextra -Wshadow -Wpedantic
  -Wnon-virtual-dtor -Wcast-align -Woverloaded-virtual)
# GCC 12 reports -Wrestrict inside libstdc++'s std::string operator+ at -O2/-O3 on
# correct code (GCC bug 105329/105651); keep it off there so -Werror stays meaningful.
if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU" AND CMAKE_CXX_COMPILER_VERSION VERSION_LESS 13)
  target_compile_options(geoslice_warnings INTERFACE -Wno-restrict)
endif()
if(GEOSLICE_WERROR)
  target_compile_options(geoslice_warnings INTERFACE -Werror)
endif()

# Invariant checks (GS_ASSERT) stay on in release builds; only NDEBUG asserts vanish.
if(GEOSLICE_SANITIZE)
  add_compile_options(-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined)
  add_link_options(-fsanitize=address,undefined)
endif()
# Fuzz builds instrument every library for coverage and ASan/UBSan; only the fuzz targets
# link libFuzzer's main (tests/fuzz/CMakeLists.txt).
if(GEOSLICE_FUZZ)
  add_compile_options(-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer)
  add_link_options(-fsanitize=address,undefined)
endif()
if(GEOSLICE_TSAN)
  add_compile_options(-fsanitize=thread -fno-omit-frame-pointer)
  add_link_options(-fsanitize=thread)
endif()
