# `cmake --install`: the `geoslice` executable (component runtime: what the container image
# installs), and for C++ users the libraries, their headers under include/geoslice/ and an
# exported CMake package (component dev):
#   find_package(geoslice REQUIRED)
#   target_link_libraries(app PRIVATE geoslice::geoslice_api)
# tests/install/ builds and runs such a consumer against an installed tree.
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(GEOSLICE_LIBRARY_FOLDERS model view image section bake renderer print api workers server)
set(GEOSLICE_LIBRARY_TARGETS "")
foreach(folder IN LISTS GEOSLICE_LIBRARY_FOLDERS)
  list(APPEND GEOSLICE_LIBRARY_TARGETS geoslice_${folder})
endforeach()

install(TARGETS geoslice RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT runtime)
# geoslice_warnings and geoslice_geographiclib are interface targets the libraries link
# privately; a static library's private links travel with it, so they are exported too.
install(TARGETS ${GEOSLICE_LIBRARY_TARGETS} geoslice_warnings geoslice_geographiclib
  EXPORT geosliceTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT dev
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/geoslice)
foreach(folder IN LISTS GEOSLICE_LIBRARY_FOLDERS)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/${folder}/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/geoslice/${folder}
    COMPONENT dev FILES_MATCHING PATTERN "*.hpp")
endforeach()
install(FILES ${PROJECT_BINARY_DIR}/generated/model/version.hpp
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/geoslice/model COMPONENT dev)
install(EXPORT geosliceTargets NAMESPACE geoslice:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geoslice COMPONENT dev)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/geosliceConfig.cmake.in
  ${PROJECT_BINARY_DIR}/geosliceConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geoslice)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/geosliceConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/geosliceConfig.cmake ${PROJECT_BINARY_DIR}/geosliceConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/geoslice COMPONENT dev)
