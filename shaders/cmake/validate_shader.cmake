# Resolves the includes of one GLSL stage and validates it with glslangValidator.
#
#   cmake -DSTAGE=<shaders/x.vert> -DROOT=<shaders/> -DOUTPUT=<build/.../x.vert>
#         -DVALIDATOR=<glslangValidator> -P validate_shader.cmake
#
# Each line `#include "path"` (relative to the including file) is replaced by that file,
# framed by `#line` directives: `#line 1 N` before it and `#line <next line> <parent>`
# after it, where N numbers the files of this stage in the order they are first met
# (0 = the stage itself). A file is pasted once per stage; a second include of it becomes
# an empty line. The driver and glslangValidator report errors as "N:line", so the
# numbers map back to files: OUTPUT.files holds "0 = x.vert, 1 = include/y.glsl", which
# the program embeds next to the text.
#
# The resolved text is checked by glslangValidator as the OpenGL driver will compile it:
# GLSL with the stage's own `#version 450 core`, OpenGL (not SPIR-V) semantics, the stage
# from the file extension (.vert, .frag, .comp). On an error every message is printed as
# "<file>:<line>: error: <message>" with the original file and line, and the script
# fails (OUTPUT is not written).

cmake_minimum_required(VERSION 3.25)

foreach(var STAGE ROOT OUTPUT VALIDATOR)
  if(NOT DEFINED ${var} OR "${${var}}" STREQUAL "")
    message(FATAL_ERROR "validate_shader.cmake: -D${var}=... is required")
  endif()
endforeach()

# Sets <out_var> to the text of `path` with its includes resolved; `path` gets the next
# source-string number.
function(_shader_resolve path out_var)
  get_property(files GLOBAL PROPERTY _shader_files)
  list(LENGTH files id)
  list(APPEND files "${path}")
  set_property(GLOBAL PROPERTY _shader_files "${files}")
  file(READ "${path}" content)
  get_filename_component(dir "${path}" DIRECTORY)
  set(text "")
  set(line_no 0)
  while(NOT content STREQUAL "")
    string(FIND "${content}" "\n" newline)
    if(newline EQUAL -1)
      set(line "${content}")
      set(content "")
    else()
      string(SUBSTRING "${content}" 0 ${newline} line)
      math(EXPR rest "${newline} + 1")
      string(SUBSTRING "${content}" ${rest} -1 content)
    endif()
    string(REGEX REPLACE "\r$" "" line "${line}")
    math(EXPR line_no "${line_no} + 1")
    if(line MATCHES "^[ \t]*#[ \t]*include[ \t]+\"([^\"]+)\"[ \t]*(//.*)?$")
      get_filename_component(child "${CMAKE_MATCH_1}" ABSOLUTE BASE_DIR "${dir}")
      if(NOT EXISTS "${child}" OR IS_DIRECTORY "${child}")
        message(NOTICE "${path}:${line_no}: error: include \"${CMAKE_MATCH_1}\" not found (looked for ${child})")
        set_property(GLOBAL PROPERTY _shader_failed TRUE)
        string(APPEND text "\n")
        continue()
      endif()
      get_property(files GLOBAL PROPERTY _shader_files)
      if("${child}" IN_LIST files)
        string(APPEND text "\n")   # already pasted: keep the line count
        continue()
      endif()
      list(LENGTH files child_id)
      _shader_resolve("${child}" child_text)
      math(EXPR next_line "${line_no} + 1")
      string(APPEND text "#line 1 ${child_id}\n${child_text}#line ${next_line} ${id}\n")
    elseif(line MATCHES "^[ \t]*#[ \t]*include")
      message(NOTICE "${path}:${line_no}: error: malformed #include: write #include \"relative/path.glsl\"")
      set_property(GLOBAL PROPERTY _shader_failed TRUE)
      string(APPEND text "\n")
    else()
      string(APPEND text "${line}\n")
    endif()
  endwhile()
  set(${out_var} "${text}" PARENT_SCOPE)
endfunction()

# Fails the script after the messages printed so far; they are the error report.
macro(_shader_fail)
  file(REMOVE "${OUTPUT}" "${OUTPUT}.files")
  if(CMAKE_VERSION VERSION_GREATER_EQUAL 3.29)
    cmake_language(EXIT 1)
  else()
    message(FATAL_ERROR "shaders: ${STAGE} is not valid GLSL (messages above)")
  endif()
endmacro()

get_filename_component(STAGE "${STAGE}" ABSOLUTE)
get_filename_component(ROOT "${ROOT}" ABSOLUTE)
set_property(GLOBAL PROPERTY _shader_files "")
set_property(GLOBAL PROPERTY _shader_failed FALSE)
_shader_resolve("${STAGE}" resolved)
get_property(failed GLOBAL PROPERTY _shader_failed)
if(failed)
  _shader_fail()
endif()
get_property(files GLOBAL PROPERTY _shader_files)

# Validate a copy with the stage's extension (glslangValidator picks the stage from it).
get_filename_component(ext "${STAGE}" LAST_EXT)
get_filename_component(out_dir "${OUTPUT}" DIRECTORY)
file(MAKE_DIRECTORY "${out_dir}")
set(candidate "${OUTPUT}.check${ext}")
file(WRITE "${candidate}" "${resolved}")
execute_process(COMMAND "${VALIDATOR}" "${candidate}"
                RESULT_VARIABLE rc OUTPUT_VARIABLE log ERROR_VARIABLE log)
file(REMOVE "${candidate}")

# Map "ERROR: N:line: message" back to the original file and line.
string(ASCII 1 semicolon)   # stands in for ';' while the log is a CMake list
string(REPLACE ";" "${semicolon}" log_list "${log}")
string(REPLACE "\n" ";" log_list "${log_list}")
set(mapped FALSE)
foreach(entry IN LISTS log_list)
  string(REPLACE "${semicolon}" ";" entry "${entry}")
  if(entry MATCHES "^(ERROR|WARNING): ([0-9]+):([0-9]+): (.*)$")
    set(kind error)
    if(CMAKE_MATCH_1 STREQUAL "WARNING")
      set(kind warning)
    endif()
    set(source "${CMAKE_MATCH_2}")
    set(line "${CMAKE_MATCH_3}")
    string(STRIP "${CMAKE_MATCH_4}" what)
    list(LENGTH files count)
    if(source LESS count)
      list(GET files ${source} file)
    else()
      set(file "${STAGE} (source string ${source})")
    endif()
    message(NOTICE "${file}:${line}: ${kind}: ${what}")
    set(mapped TRUE)
  endif()
endforeach()
if(NOT rc EQUAL 0)
  if(NOT mapped)  # an error without a location (e.g. a link error): show the whole log
    message(NOTICE "${STAGE}: error: glslangValidator failed (exit ${rc}):\n${log}")
  endif()
  _shader_fail()
endif()

# The legend of source-string numbers, paths relative to ROOT.
set(legend "")
set(index 0)
foreach(file IN LISTS files)
  file(RELATIVE_PATH rel "${ROOT}" "${file}")
  if(index GREATER 0)
    string(APPEND legend ", ")
  endif()
  string(APPEND legend "${index} = ${rel}")
  math(EXPR index "${index} + 1")
endforeach()
file(WRITE "${OUTPUT}" "${resolved}")
file(WRITE "${OUTPUT}.files" "${legend}")
