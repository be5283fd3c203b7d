# Decides whether the Python module (python/, docs/python.md) is built, and finds what it needs:
# a Python 3 interpreter that imports numpy, its development headers and pybind11 (Debian:
# python3-dev python3-numpy python3-pybind11; the tests also need python3-pytest).
#
# BOUNCECAL_BUILD_PYTHON defaults to ON when all of them are found and bouncecal is the top-level
# project, and to OFF in the sanitized and fuzzing builds (an instrumented extension cannot be
# loaded into an uninstrumented interpreter). Given ON explicitly, a missing piece is an error
# naming it; left to its default, the module is skipped with a message instead.
#
# The interpreter is the first `python3` on PATH that imports numpy, unless Python3_EXECUTABLE
# names one: a pyenv or virtualenv shim ahead of /usr/bin on PATH often has no numpy, and a module
# built for it could not be tested or used with the Debian numpy.
set(bouncecal_python_wanted ON)
if(DEFINED BOUNCECAL_BUILD_PYTHON)
  set(bouncecal_python_wanted ${BOUNCECAL_BUILD_PYTHON})
elseif(NOT PROJECT_IS_TOP_LEVEL OR BOUNCECAL_SANITIZE OR BOUNCECAL_FUZZ)
  set(bouncecal_python_wanted OFF)
endif()

set(bouncecal_python_found OFF)
set(bouncecal_python_missing "")
if(bouncecal_python_wanted)
  if(NOT Python3_EXECUTABLE)
    function(bouncecal_python_imports_numpy result candidate)
      execute_process(COMMAND "${candidate}" -c "import numpy"
        RESULT_VARIABLE status OUTPUT_QUIET ERROR_QUIET)
      if(NOT status EQUAL 0)
        set(${result} FALSE PARENT_SCOPE)
      endif()
    endfunction()
    find_program(BOUNCECAL_PYTHON3_WITH_NUMPY NAMES python3
      VALIDATOR bouncecal_python_imports_numpy
      DOC "The Python interpreter the module is built and tested for (imports numpy)")
    if(BOUNCECAL_PYTHON3_WITH_NUMPY)
      set(Python3_EXECUTABLE "${BOUNCECAL_PYTHON3_WITH_NUMPY}")
    else()
      list(APPEND bouncecal_python_missing "a python3 on PATH that imports numpy (python3-numpy)")
    endif()
  endif()
  if(NOT bouncecal_python_missing)
    find_package(Python3 3.9 QUIET COMPONENTS Interpreter Development.Module)
    if(NOT Python3_FOUND)
      list(APPEND bouncecal_python_missing
        "the development files of ${Python3_EXECUTABLE} (python3-dev)")
    endif()
  endif()
  if(NOT bouncecal_python_missing)
    # After Python3, so pybind11 uses that interpreter (its FindPython mode).
    find_package(pybind11 2.10 CONFIG QUIET)
    if(NOT pybind11_FOUND)
      list(APPEND bouncecal_python_missing "pybind11 >= 2.10 (python3-pybind11)")
    endif()
  endif()
  if(NOT bouncecal_python_missing)
    set(bouncecal_python_found ON)
  endif()
endif()

option(BOUNCECAL_BUILD_PYTHON
  "Build the Python module bouncecal (needs python3 with numpy, python3-dev, pybind11)"
  ${bouncecal_python_found})
if(BOUNCECAL_BUILD_PYTHON AND NOT bouncecal_python_found)
  list(JOIN bouncecal_python_missing ", " missing)
  message(FATAL_ERROR "BOUNCECAL_BUILD_PYTHON is ON but bouncecal could not find ${missing}; "
    "install it (scripts/install_deps.sh --tests), name the interpreter with -DPython3_EXECUTABLE=..., "
    "or configure with -DBOUNCECAL_BUILD_PYTHON=OFF")
elseif(NOT BOUNCECAL_BUILD_PYTHON AND bouncecal_python_wanted AND bouncecal_python_missing)
  list(JOIN bouncecal_python_missing ", " missing)
  message(STATUS "bouncecal: the Python module is not built: ${missing} not found")
elseif(BOUNCECAL_BUILD_PYTHON)
  message(STATUS "bouncecal: Python module for ${Python3_EXECUTABLE} "
    "(${Python3_VERSION}, pybind11 ${pybind11_VERSION})")
endif()
