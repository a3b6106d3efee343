# make install: the libraries, their headers and the CMake package laserfit, so that another
# project links only the stages it needs:
#   find_package(laserfit 0.1 REQUIRED COMPONENTS registration)
#   target_link_libraries(app PRIVATE laserfit::registration)
# One export file per component (laserfit_<name>_targets.cmake); laserfitConfig.cmake loads the
# requested components, the components they need, and only their third-party packages.
include(CMakePackageConfigHelpers)
get_property(LASERFIT_INSTALLED_COMPONENTS GLOBAL PROPERTY LASERFIT_COMPONENTS)
configure_package_config_file(cmake/laserfitConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/laserfitConfig.cmake INSTALL_DESTINATION ${LASERFIT_CMAKE_DIR})
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/laserfitConfigVersion.cmake
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/laserfitConfig.cmake
              ${CMAKE_CURRENT_BINARY_DIR}/laserfitConfigVersion.cmake
        DESTINATION ${LASERFIT_CMAKE_DIR})
install(FILES LICENSE DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/laserfit OPTIONAL)
