# Run by ctest (tests/install/CMakeLists.txt) as `cmake -P` with BUILD_DIR, SOURCE_DIR, WORK_DIR,
# GENERATOR, CXX_COMPILER, BUILD_TYPE, CXX_FLAGS (may be empty), LIBDIR (the build's
# CMAKE_INSTALL_LIBDIR), IN_TREE (the in-tree consumer's path, or empty) and TOOL (the tool's file
# name, or empty). Fails with a message at the first
# step that goes wrong.
cmake_minimum_required(VERSION 3.25)

set(prefix ${WORK_DIR}/prefix)
set(consumer_build ${WORK_DIR}/consumer-build)
file(REMOVE_RECURSE ${WORK_DIR})
file(MAKE_DIRECTORY ${WORK_DIR})

function(run_step what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE output ERROR_VARIABLE error)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${ARGN}\n--- stdout\n${output}\n--- stderr\n${error}")
  endif()
  set(step_output "${output}" PARENT_SCOPE)
endfunction()

# 1. Install the build tree.
run_step("cmake --install" ${CMAKE_COMMAND} --install ${BUILD_DIR} --prefix ${prefix})
foreach(file include/clothsim/sim/simulation.h include/clothsim/scene/scene.h include/clothsim/core/vec3.h
             ${LIBDIR}/libclothsim_core.a ${LIBDIR}/libclothsim_io.a ${LIBDIR}/cmake/clothsim/clothsimConfig.cmake
             ${LIBDIR}/cmake/clothsim/clothsimConfigVersion.cmake ${LIBDIR}/cmake/clothsim/clothsimTargets.cmake)
  if(NOT EXISTS ${prefix}/${file})
    message(FATAL_ERROR "cmake --install left out ${file}")
  endif()
endforeach()
if(TOOL AND NOT EXISTS ${prefix}/bin/${TOOL})
  message(FATAL_ERROR "cmake --install left out bin/${TOOL}")
endif()

# 2. Configure the consumer against the prefix alone: no package registry, no source tree.
set(flags_arg "")
if(CXX_FLAGS)
  set(flags_arg -DCMAKE_CXX_FLAGS=${CXX_FLAGS} -DCMAKE_EXE_LINKER_FLAGS=${CXX_FLAGS})
endif()
run_step("configuring the consumer" ${CMAKE_COMMAND} -S ${SOURCE_DIR}/examples/consumer -B ${consumer_build}
         -G ${GENERATOR} -DCMAKE_CXX_COMPILER=${CXX_COMPILER} -DCMAKE_BUILD_TYPE=${BUILD_TYPE}
         -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_PACKAGE_NO_PACKAGE_REGISTRY=ON -DCMAKE_EXPORT_COMPILE_COMMANDS=ON
         ${flags_arg})
if(NOT step_output MATCHES "clothsim 0\\.[0-9]+\\.[0-9]+ from ${prefix}/")
  message(FATAL_ERROR "the consumer did not find clothsim in ${prefix}:\n${step_output}")
endif()

# 3. Build it; it must compile against the installed headers, not the source tree's.
run_step("building the consumer" ${CMAKE_COMMAND} --build ${consumer_build})
file(READ ${consumer_build}/compile_commands.json commands)
string(FIND "${commands}" "${SOURCE_DIR}/src" source_include)
if(NOT source_include EQUAL -1)
  message(FATAL_ERROR "the consumer compiled against ${SOURCE_DIR}/src:\n${commands}")
endif()
if(NOT commands MATCHES "${prefix}/include/clothsim")
  message(FATAL_ERROR "the consumer does not include ${prefix}/include/clothsim:\n${commands}")
endif()

# 4. Run it: paper-fig5 to t = 1 s, the numbers the in-tree build prints, byte for byte.
run_step("running the consumer" ${consumer_build}/consumer paper-fig5)
set(installed "${step_output}")
if(NOT installed MATCHES "^scene paper-fig5: [0-9]+ particles, t = 1 s, [0-9]+ steps\nenergy -?[0-9]")
  message(FATAL_ERROR "unexpected consumer output:\n${installed}")
endif()
if(IN_TREE)
  run_step("running the in-tree consumer" ${IN_TREE} paper-fig5)
  if(NOT installed STREQUAL step_output)
    message(FATAL_ERROR "installed and in-tree consumers differ:\n--- installed\n${installed}--- in tree\n${step_output}")
  endif()
endif()
message(STATUS "consumer against ${prefix}:\n${installed}")
