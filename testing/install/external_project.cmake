# cmake -DSTAGE=<staged install> -DSOURCE=<external project> -DBINARY=<its build folder> -P external_project.cmake
# Configures and builds the external project against the staged install only (CMAKE_PREFIX_PATH=<STAGE>/usr,
# no package registry), checks that find_package(Whitted) took the staged package and that the program loads
# the staged library, then runs it (it renders and checks its pixels; needs an X display).
file(REMOVE_RECURSE "${BINARY}")
function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE out)
  message("${out}")
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result})")
  endif()
  set(out "${out}" PARENT_SCOPE)
endfunction()

run(configure "${CMAKE_COMMAND}" -S "${SOURCE}" -B "${BINARY}" -G Ninja -DCMAKE_BUILD_TYPE=Release
  "-DCMAKE_PREFIX_PATH=${STAGE}/usr" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
file(STRINGS "${BINARY}/CMakeCache.txt" whitted_dir REGEX "^Whitted_DIR:")
message("${whitted_dir}")
if(NOT whitted_dir MATCHES "^Whitted_DIR:PATH=${STAGE}/usr/lib/")
  message(FATAL_ERROR "find_package(Whitted) did not take the staged package")
endif()
run(build "${CMAKE_COMMAND}" --build "${BINARY}")
run(ldd ldd "${BINARY}/whitted_installed")
if(NOT out MATCHES "libvtkWhitted[^ ]* => ${STAGE}/usr/lib/")
  message(FATAL_ERROR "the program does not load the staged libvtkWhitted")
endif()
run(whitted_installed "${BINARY}/whitted_installed")
