# ParaViewDebian.cmake -- find Debian 12's ParaView 5.11 (paraview-dev) for the Whitted plugin build.
#
# WHY THIS FILE EXISTS: Debian splits ParaView 5.11 so that `paraview-dev` alone cannot be used by
# find_package(ParaView): its CMake package references files that only `python3-paraview` ships, and
# `python3-paraview` cannot be installed next to `python3-vtk9` (both own dist-packages/vtkmodules),
# which the VTK half of this project needs. Every work-around for that packaging lives here and
# nowhere else, one "Trap" per problem. Delete this file when building against a ParaView SDK or a
# ParaView built from source (a plain find_package(ParaView COMPONENTS RemotingViews) then works).
#
# Usage (in the directory that builds the plugin; the project must enable C and CXX):
#   set(PARAVIEW_DEBIAN_COMPONENTS RemotingViews)   # optional, this is the default
#   include(ParaViewDebian)
# Result: ParaView_FOUND, ParaView::* / VTK::* (ParaView's bundled VTK) targets,
# and the paraview_* / vtk_module_* CMake API.
#
# Prerequisite (python3-paraview conflicts with python3-vtk9, so never dpkg -i it):
#   apt-get download python3-paraview && dpkg -x python3-paraview_*.deb <prefix>
# and pass -DPARAVIEW_DEBIAN_PYTHON_PREFIX=<prefix> (./whitted.sh uses build/pvprefix).

# Trap 1: python3-paraview is not installed, but paraview-dev's exported target
# files reference files that only it ships.  CMake's generated *-targets.cmake
# FATAL_ERRORs on a missing IMPORTED_LOCATION, but returns early without
# checking anything if *all* targets of its export set already exist.
set(PARAVIEW_DEBIAN_PYTHON_PREFIX "${PROJECT_BINARY_DIR}/../pvprefix" CACHE PATH
  "Directory into which python3-paraview_*.deb was unpacked with dpkg -x")
# Where Debian's paraview-dev installs its CMake package.
set(PARAVIEW_DEBIAN_CMAKE_DIR "/usr/lib/x86_64-linux-gnu/cmake/paraview-5.11" CACHE PATH
  "Debian's ParaView CMake package directory")
if (NOT DEFINED PARAVIEW_DEBIAN_COMPONENTS)
  # A plain find_package(ParaView) asks for every component, incl. the Qt
  # client ones, which need Qt5 development files; RemotingViews is enough
  # for a view/representation plugin (and pulls in everything below it).
  set(PARAVIEW_DEBIAN_COMPONENTS RemotingViews)
endif ()

# Trap 2: ParaView's config calls find_package(VTK PATHS <its vtk dir>
# NO_DEFAULT_PATH), but a VTK_DIR cache/normal variable (e.g. left from an
# earlier find_package(VTK) of Debian's *system* VTK 9.1) wins over PATHS, and
# then ParaView gets the wrong VTK and fails.  Point it at ParaView's own VTK.
# The caller's cached VTK_DIR is saved here and restored at the end of this file.
if (DEFINED CACHE{VTK_DIR})
  set(_pvdeb_saved_vtk_dir "$CACHE{VTK_DIR}")
endif ()
unset(VTK_DIR CACHE)
unset(VTK_DIR)
set(VTK_DIR "${PARAVIEW_DEBIAN_CMAKE_DIR}/vtk")

# Trap 3: ParaView's VTK::Python target links Python3::Module, which its config
# does not create ("The link interface of target VTK::Python contains:
# Python3::Module but the target was not found").  Find Python first.
# The first python3 on PATH may not be Debian's 3.11: configure with
# -DPython3_EXECUTABLE=/usr/bin/python3.
find_package(Python3 REQUIRED COMPONENTS Interpreter Development.Module)

# Trap 1 (cont.): predefine, as empty INTERFACE IMPORTED libraries, every target
# of the three export sets whose files are missing:
#   vtk/VTKPython-targets.cmake    -> dist-packages/vtkmodules/*.so  (python3-paraview)
#   ParaViewPython-targets.cmake   -> dist-packages/paraview/modules/*.so (python3-paraview)
#   ParaViewTools-targets.cmake    -> /usr/bin/pvpython (python3-paraview)
# The list is read from each file's "foreach(_cmake_expected_target IN ITEMS ...)"
# line, so it stays correct if Debian rebuilds the package.
foreach (_pvdeb_file IN ITEMS
    "${PARAVIEW_DEBIAN_CMAKE_DIR}/vtk/VTKPython-targets.cmake"
    "${PARAVIEW_DEBIAN_CMAKE_DIR}/ParaViewPython-targets.cmake"
    "${PARAVIEW_DEBIAN_CMAKE_DIR}/ParaViewTools-targets.cmake")
  if (NOT EXISTS "${_pvdeb_file}")
    continue ()
  endif ()
  file(STRINGS "${_pvdeb_file}" _pvdeb_line REGEX "foreach\\(_cmake_expected_target IN ITEMS ")
  string(REGEX REPLACE ".*IN ITEMS ([^)]*)\\).*" "\\1" _pvdeb_targets "${_pvdeb_line}")
  separate_arguments(_pvdeb_targets UNIX_COMMAND "${_pvdeb_targets}")
  foreach (_pvdeb_target IN LISTS _pvdeb_targets)
    if (NOT TARGET "${_pvdeb_target}")
      add_library("${_pvdeb_target}" INTERFACE IMPORTED)
    endif ()
  endforeach ()
endforeach ()

# Trap 6: C must be enabled.  ParaView's VTK::mpi links MPI::MPI_C, which
# find_package(MPI) only creates when C is enabled; otherwise: "The link
# interface of target VTK::mpi contains: MPI::MPI_C but the target was not found".
get_property(_pvdeb_languages GLOBAL PROPERTY ENABLED_LANGUAGES)
if (NOT "C" IN_LIST _pvdeb_languages)
  message(FATAL_ERROR "ParaViewDebian: enable the C language in project() (needed by ParaView's MPI dependency)")
endif ()

# Trap 7 (cosmetic): ParaView's config asks its VTK for the component by its old name "vtkm", and VTK's
# config answers every configure with a "CMake Deprecation Warning ... The new name for the 'vtkm'
# component is 'm'". Nothing to act on for us: silence deprecation messages during the lookup only.
if (DEFINED CMAKE_WARN_DEPRECATED)
  set(_pvdeb_warn_deprecated "${CMAKE_WARN_DEPRECATED}")
endif ()
set(CMAKE_WARN_DEPRECATED OFF)
find_package(ParaView REQUIRED COMPONENTS ${PARAVIEW_DEBIAN_COMPONENTS})
if (DEFINED _pvdeb_warn_deprecated)
  set(CMAKE_WARN_DEPRECATED "${_pvdeb_warn_deprecated}")
  unset(_pvdeb_warn_deprecated)
else ()
  unset(CMAKE_WARN_DEPRECATED)
endif ()

# Trap 4: client-server wrapping (paraview_add_plugin / vtk_module_wrap_client_server)
# reads the *-hierarchy.txt of every module the plugin depends on.  paraview-dev's
# module properties point at /usr/lib/x86_64-linux-gnu/vtk/hierarchy/ParaView/,
# but Debian ships those files only in python3-paraview.  Re-point every imported
# target's INTERFACE_vtk_module_hierarchy into the unpacked python3-paraview.
set(_pvdeb_hier_dir "${PARAVIEW_DEBIAN_PYTHON_PREFIX}/usr/lib/x86_64-linux-gnu/vtk/hierarchy/ParaView")
if (NOT IS_DIRECTORY "${_pvdeb_hier_dir}")
  message(FATAL_ERROR
    "ParaViewDebian: ${_pvdeb_hier_dir} not found. Run\n"
    "  apt-get download python3-paraview && dpkg -x python3-paraview_*.deb <prefix>\n"
    "and configure with -DPARAVIEW_DEBIAN_PYTHON_PREFIX=<prefix>.")
endif ()
get_property(_pvdeb_imported DIRECTORY PROPERTY IMPORTED_TARGETS)  # CMake >= 3.21
set(_pvdeb_fixed 0)
foreach (_pvdeb_target IN LISTS _pvdeb_imported)
  get_property(_pvdeb_hier TARGET "${_pvdeb_target}" PROPERTY INTERFACE_vtk_module_hierarchy)
  if (_pvdeb_hier AND NOT EXISTS "${_pvdeb_hier}")
    get_filename_component(_pvdeb_name "${_pvdeb_hier}" NAME)
    if (EXISTS "${_pvdeb_hier_dir}/${_pvdeb_name}")
      set_property(TARGET "${_pvdeb_target}" PROPERTY
        INTERFACE_vtk_module_hierarchy "${_pvdeb_hier_dir}/${_pvdeb_name}")
      math(EXPR _pvdeb_fixed "${_pvdeb_fixed} + 1")
    endif ()
  endif ()
endforeach ()
message(STATUS "ParaViewDebian: ParaView ${ParaView_VERSION}; re-pointed ${_pvdeb_fixed} hierarchy files to ${_pvdeb_hier_dir}")

# Trap 5: paraview_add_plugin() defaults to XML_DOCUMENTATION ON and, because
# Debian's ParaView is a Qt build (PARAVIEW_USE_QT=ON), then generates Qt help
# (paraview_client_generate_help -> find_package(Qt5 ...)).  paraview-dev does not
# pull in Qt5 development files, so configure fails with "Could not find a package
# configuration file provided by Qt5".  PARAVIEW_USE_QT is read by the plugin
# macros only for that documentation step, so turn it off when Qt5 is missing.
# (Per-plugin alternative: paraview_plugin_build(... DISABLE_XML_DOCUMENTATION ON).)
find_package(Qt5 QUIET COMPONENTS Core Help)
if (NOT Qt5_FOUND)
  set(PARAVIEW_USE_QT OFF)
endif ()

# Trap 2 (cont.): the unset(VTK_DIR CACHE) above deleted the caller's cached
# VTK_DIR (e.g. -DVTK_DIR=... or the entry a sibling directory's
# find_package(VTK) of Debian's system VTK 9.1 created).  Put it back so the
# sibling keeps finding the same VTK on re-configure.  The normal variable
# VTK_DIR (ParaView's VTK) stays set in this directory scope only -- so include()
# this file in the subdirectory that builds the plugin, not at top level, if the
# project also uses system VTK (seen working: sysvtk/ + pv/ siblings, configure,
# re-configure and build).
if (DEFINED _pvdeb_saved_vtk_dir)
  set(VTK_DIR "${_pvdeb_saved_vtk_dir}" CACHE PATH "The directory containing a CMake configuration file for VTK." FORCE)
else ()
  unset(VTK_DIR CACHE)
endif ()
set(VTK_DIR "${PARAVIEW_DEBIAN_CMAKE_DIR}/vtk")
unset(_pvdeb_saved_vtk_dir)

unset(_pvdeb_file)
unset(_pvdeb_line)
unset(_pvdeb_targets)
unset(_pvdeb_target)
unset(_pvdeb_languages)
unset(_pvdeb_imported)
unset(_pvdeb_hier)
unset(_pvdeb_name)
unset(_pvdeb_fixed)
