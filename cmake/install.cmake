# What `cmake --install <build> --prefix P` puts under P (docs/library.md); the rules are here but
# for the tool's, which apps/clothsim/CMakeLists.txt adds (see the end of this file):
#
#   lib/libclothsim_<module>.a          the static libraries of src/ (src/CMakeLists.txt)
#   include/clothsim/<module>/*.h       their headers, as in src/, so that the include lines of the
#                                       build (#include "sim/simulation.h") work unchanged
#   lib/cmake/clothsim/                 the CMake package: clothsimConfig.cmake,
#                                       clothsimConfigVersion.cmake, clothsimTargets.cmake
#                                       (clothsim::clothsim and clothsim::<module>), and with the
#                                       renderer clothsimRenderTargets.cmake (clothsim::render
#                                       and clothsim::run, which draws a run's pictures with it)
#   bin/clothsim                        the command-line tool, when built (apps/clothsim)
#
# Install components: `library` (libraries, headers, package) and `tool` (the executable), e.g.
# `cmake --install build/release --prefix P --component library`.
#
# The renderer is an optional component of the package (find_package(clothsim COMPONENTS render)):
# it needs epoxy (through pkg-config) and libpng wherever it is linked, and the simulation needs
# neither, so a plain find_package(clothsim) asks for no graphics packages at all. The component
# also brings clothsim::run (run_scene: a run into an output folder, pictures included).
#
# Rejected: headers straight under include/ (include/sim/simulation.h would collide with other
# projects' folders named core/, model/, io/), and one export set for everything (a program that
# only simulates would then need epoxy and libpng installed to configure).

# Install rules by default only when clothsim is the top-level project; a project that embeds it
# with add_subdirectory and installs itself decides whether clothsim's files go with it.
option(CLOTHSIM_INSTALL "Generate clothsim's install rules and CMake package" ${clothsim_top_level})
if(NOT CLOTHSIM_INSTALL)
  return()
endif()

include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

set(CLOTHSIM_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/clothsim" CACHE STRING
    "Where the CMake package goes, relative to the prefix")
set(clothsim_include_dir "${CMAKE_INSTALL_INCLUDEDIR}/clothsim")

get_property(clothsim_modules GLOBAL PROPERTY CLOTHSIM_MODULES)
list(REMOVE_ITEM clothsim_modules clothsim_render clothsim_run)
# The run module (src/run) links the renderer where that is built, so it goes with it; without the
# renderer it is plain simulation code and goes with the rest.
if(NOT TARGET clothsim_render)
  list(APPEND clothsim_modules clothsim_run)
endif()

install(TARGETS ${clothsim_modules} clothsim
  EXPORT clothsimTargets
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT library
  INCLUDES DESTINATION ${clothsim_include_dir})
install(EXPORT clothsimTargets
  NAMESPACE clothsim::
  DESTINATION ${CLOTHSIM_INSTALL_CMAKEDIR}
  COMPONENT library)

# Every header of src/ (a module's internal headers too: the public ones include them), and the
# element formulas forces/element.h includes (element_math.inc). The renderer's only with the
# renderer; the Vulkan module's (the backend's integrator, which sim links) only with it.
set(clothsim_header_excludes "")
if(NOT TARGET clothsim_gpu)
  list(APPEND clothsim_header_excludes PATTERN gpu EXCLUDE)
endif()
if(NOT TARGET clothsim_render)
  list(APPEND clothsim_header_excludes PATTERN render EXCLUDE)
endif()
install(DIRECTORY ${PROJECT_SOURCE_DIR}/src/
  DESTINATION ${clothsim_include_dir}
  COMPONENT library
  FILES_MATCHING PATTERN "*.h" PATTERN "*.inc" ${clothsim_header_excludes})

if(TARGET clothsim_render)
  install(TARGETS clothsim_render clothsim_run
    EXPORT clothsimRenderTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT library
    INCLUDES DESTINATION ${clothsim_include_dir})
  install(EXPORT clothsimRenderTargets
    NAMESPACE clothsim::
    DESTINATION ${CLOTHSIM_INSTALL_CMAKEDIR}
    COMPONENT library)
  set(CLOTHSIM_PACKAGE_HAS_RENDER TRUE)
else()
  set(CLOTHSIM_PACKAGE_HAS_RENDER FALSE)
endif()

if(TARGET clothsim_gpu)
  set(CLOTHSIM_PACKAGE_HAS_VULKAN TRUE)
else()
  set(CLOTHSIM_PACKAGE_HAS_VULKAN FALSE)
endif()
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/clothsimConfig.cmake.in
  ${CMAKE_CURRENT_BINARY_DIR}/clothsimConfig.cmake
  INSTALL_DESTINATION ${CLOTHSIM_INSTALL_CMAKEDIR})
# 0.x: a minor version may change the API (docs/library.md, "Stability").
write_basic_package_version_file(${CMAKE_CURRENT_BINARY_DIR}/clothsimConfigVersion.cmake
  VERSION ${PROJECT_VERSION}
  COMPATIBILITY SameMinorVersion)
install(FILES ${CMAKE_CURRENT_BINARY_DIR}/clothsimConfig.cmake ${CMAKE_CURRENT_BINARY_DIR}/clothsimConfigVersion.cmake
  DESTINATION ${CLOTHSIM_INSTALL_CMAKEDIR}
  COMPONENT library)

# The tool (apps/clothsim) and the Python module (python/) come after this file and install
# themselves, under `if(CLOTHSIM_INSTALL)`, into the GNUInstallDirs destinations set here:
# the tool into ${CMAKE_INSTALL_BINDIR} (component tool), the module into its site-packages
# folder (component python).
