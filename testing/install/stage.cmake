# cmake -DBUILD=<build tree> -DSTAGE=<folder> [-DCOMPONENT=<install component>] -P stage.cmake
# Installs the build tree as its package does (prefix /usr; the package's component, if it has one) into a fresh
# staging folder: DESTDIR=<STAGE>.
file(REMOVE_RECURSE "${STAGE}")
set(ENV{DESTDIR} "${STAGE}")
set(component)
if(COMPONENT)
  set(component --component "${COMPONENT}")
endif()
execute_process(COMMAND "${CMAKE_COMMAND}" --install "${BUILD}" --prefix /usr ${component}
  RESULT_VARIABLE result)
if(NOT result EQUAL 0)
  message(FATAL_ERROR "cmake --install ${BUILD} failed: ${result}")
endif()
