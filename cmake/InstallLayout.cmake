# Where OpenMM is, and where the plugin installs its parts beside it.
#
# Two ways in:
#  - scripts/setup.sh (a plain CMake build): OPENMM_DIR is given; everything installs under
#    CMAKE_INSTALL_PREFIX, which defaults to OPENMM_DIR, and the Python package into the
#    configured interpreter's site-packages.
#  - pip install . (scikit-build-core sets SKBUILD): OpenMM is the one the target environment
#    imports, found with `python -I`, which ignores the paths of pip's isolated build environment.
#    The wheel places the libraries where that OpenMM loads plugins: under site-packages for the
#    PyPI wheel (OpenMM.libs/lib), under the environment prefix for conda (lib/), through the
#    wheel's platlib or data directory, so that pip uninstall removes them again.
#
# Sets OPENMM_DIR (if not given), OPENMM_VERSION, and the install destinations
# RIGIDLANGEVIN_LIB_DESTINATION, RIGIDLANGEVIN_PLUGIN_DESTINATION,
# RIGIDLANGEVIN_INCLUDE_DESTINATION and RIGIDLANGEVIN_PYTHON_DESTINATION, and the installed
# absolute directories RIGIDLANGEVIN_INSTALLED_LIB_DIR and RIGIDLANGEVIN_INSTALLED_PYTHON_DIR
# (for relative RPATHs), and CMAKE_INSTALL_RPATH.

find_package(Python3 COMPONENTS Interpreter Development.Module)

set(_probe "import os, sys, sysconfig, openmm.version as v
print(os.path.dirname(v.openmm_library_path)); print(sysconfig.get_path('platlib')); print(sys.prefix); print(v.short_version)")
set(_target_platlib "")
set(_target_prefix "")
if(Python3_Interpreter_FOUND)
    execute_process(COMMAND "${Python3_EXECUTABLE}" -I -c "${_probe}" OUTPUT_VARIABLE _found RESULT_VARIABLE _status ERROR_QUIET
                    OUTPUT_STRIP_TRAILING_WHITESPACE)
    if(_status EQUAL 0)
        string(REPLACE "\n" ";" _found "${_found}")
        list(GET _found 0 _openmm_dir)
        list(GET _found 1 _target_platlib)
        list(GET _found 2 _target_prefix)
        list(GET _found 3 OPENMM_VERSION)
        if(NOT OPENMM_DIR)
            set(OPENMM_DIR "${_openmm_dir}" CACHE PATH "Where OpenMM is installed (the directory holding include/ and lib/)" FORCE)
        endif()
    endif()
endif()
if(NOT EXISTS "${OPENMM_DIR}/include/OpenMM.h")
    message(FATAL_ERROR "OPENMM_DIR='${OPENMM_DIR}' holds no include/OpenMM.h: install OpenMM 8.6 (pip install openmm==8.6.*, or conda) "
                        "into the Python environment you build for, or pass -DOPENMM_DIR=<its directory holding include/ and lib/>")
endif()

if(SKBUILD)
    if(NOT _target_platlib)
        message(FATAL_ERROR "pip install: the target environment's Python (${Python3_EXECUTABLE}) cannot import openmm; install OpenMM 8.6 first")
    endif()
    file(RELATIVE_PATH _in_platlib "${_target_platlib}" "${OPENMM_DIR}")
    file(RELATIVE_PATH _in_prefix "${_target_prefix}" "${OPENMM_DIR}")
    if(NOT _in_platlib MATCHES "^\\.\\.")
        # PyPI's openmm: OpenMM.libs inside site-packages.
        set(_root "${_in_platlib}")
    elseif(NOT _in_prefix MATCHES "^\\.\\.")
        # conda's openmm: the environment prefix.
        set(_root "${SKBUILD_DATA_DIR}/${_in_prefix}")
    else()
        message(FATAL_ERROR "OpenMM (${OPENMM_DIR}) is outside the target environment (${_target_prefix}); pip cannot install the plugin beside it")
    endif()
    string(REGEX REPLACE "/$" "" _root "${_root}")
    if(_root STREQUAL "")
        set(_prefix_of_root "")
    else()
        set(_prefix_of_root "${_root}/")
    endif()
    set(RIGIDLANGEVIN_LIB_DESTINATION "${_prefix_of_root}lib")
    set(RIGIDLANGEVIN_PLUGIN_DESTINATION "${_prefix_of_root}lib/plugins")
    set(RIGIDLANGEVIN_INCLUDE_DESTINATION "${_prefix_of_root}include/rigidlangevin")
    set(RIGIDLANGEVIN_PYTHON_DESTINATION "rigidlangevin")
    set(RIGIDLANGEVIN_INSTALLED_PYTHON_DIR "${_target_platlib}/rigidlangevin")
    # Beside OpenMM's own: the wheel's root stands for OPENMM_DIR.
    set(RIGIDLANGEVIN_INSTALLED_LIB_DIR "${OPENMM_DIR}/lib")
else()
    if(NOT CMAKE_INSTALL_PREFIX OR CMAKE_INSTALL_PREFIX_INITIALIZED_TO_DEFAULT)
        set(CMAKE_INSTALL_PREFIX "${OPENMM_DIR}" CACHE PATH "Where to install the plugin" FORCE)
    endif()
    set(RIGIDLANGEVIN_LIB_DESTINATION "lib")
    set(RIGIDLANGEVIN_PLUGIN_DESTINATION "lib/plugins")
    set(RIGIDLANGEVIN_INCLUDE_DESTINATION "include/rigidlangevin")
    set(RIGIDLANGEVIN_PYTHON_DESTINATION "${Python3_SITEARCH}/rigidlangevin")
    set(RIGIDLANGEVIN_INSTALLED_PYTHON_DIR "${Python3_SITEARCH}/rigidlangevin")
    set(RIGIDLANGEVIN_INSTALLED_LIB_DIR "${CMAKE_INSTALL_PREFIX}/lib")
endif()

# Installed libraries find OpenMM's and each other beside them (lib/, lib/plugins/), unless they
# were installed away from OpenMM.
set(CMAKE_INSTALL_RPATH "\$ORIGIN;\$ORIGIN/..")
get_filename_component(_installed "${RIGIDLANGEVIN_INSTALLED_LIB_DIR}" REALPATH)
get_filename_component(_openmm_lib "${OPENMM_DIR}/lib" REALPATH)
if(NOT _installed STREQUAL _openmm_lib)
    list(APPEND CMAKE_INSTALL_RPATH "${OPENMM_DIR}/lib" "${OPENMM_DIR}/lib/plugins")
endif()
