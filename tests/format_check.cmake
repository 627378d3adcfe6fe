# The `format` test: every C++/CUDA source under solver/, reference/, tests/ and benchmarks/ must
# be as clang-format (with the root .clang-format) would write it. Run as
#   cmake -DCLANG_FORMAT=<clang-format> -DSOURCE_DIR=<repo> [-DGIT=<git>] -P format_check.cmake
# The files are the tracked ones (git ls-files) when git and a work tree are present, else a glob.
# On failure it lists the files that differ and the command that fixes them.
cmake_minimum_required(VERSION 3.25)

if(NOT CLANG_FORMAT OR NOT SOURCE_DIR)
  message(FATAL_ERROR "format_check.cmake: pass -DCLANG_FORMAT=... and -DSOURCE_DIR=...")
endif()

set(folders solver reference tests benchmarks validation)
set(pattern "\\.(hpp|cpp|cu|cuh)$")
set(files "")
set(listed_by_git FALSE)
if(GIT)
  execute_process(COMMAND ${GIT} ls-files -- ${folders}
    WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE git_status OUTPUT_VARIABLE git_output
    ERROR_QUIET)
  if(git_status EQUAL 0)
    set(listed_by_git TRUE)
    string(REPLACE "\n" ";" git_files "${git_output}")
    foreach(file IN LISTS git_files)
      if(file MATCHES "${pattern}")
        list(APPEND files "${file}")
      endif()
    endforeach()
  endif()
endif()
if(NOT listed_by_git)  # not a git checkout (e.g. a source tarball): every file on disk
  foreach(folder IN LISTS folders)
    file(GLOB_RECURSE found RELATIVE ${SOURCE_DIR} ${SOURCE_DIR}/${folder}/*.hpp
      ${SOURCE_DIR}/${folder}/*.cpp ${SOURCE_DIR}/${folder}/*.cu ${SOURCE_DIR}/${folder}/*.cuh)
    list(APPEND files ${found})
  endforeach()
endif()
list(SORT files)
list(LENGTH files file_count)
if(file_count EQUAL 0)
  message(FATAL_ERROR "format: no source files found under ${folders} in ${SOURCE_DIR}")
endif()

# One clang-format run over all files; with --dry-run --Werror each difference is reported as
# "<file>:<line>:<col>: error: code should be clang-formatted".
execute_process(COMMAND ${CLANG_FORMAT} --style=file --dry-run --Werror ${files}
  WORKING_DIRECTORY ${SOURCE_DIR} RESULT_VARIABLE status OUTPUT_VARIABLE out ERROR_VARIABLE err)
if(status EQUAL 0)
  message(STATUS "format: ${file_count} files match .clang-format")
  return()
endif()

# Matched on the whole text, not split into lines: the quoted source lines may hold ';' or '['.
set(differing "")
string(REGEX MATCHALL "[^\n]+:[0-9]+:[0-9]+: (error|warning): code should be clang-formatted"
  reports "${out}${err}")
foreach(report IN LISTS reports)
  string(REGEX REPLACE ":[0-9]+:[0-9]+: (error|warning): code should be clang-formatted$" ""
    file "${report}")
  list(APPEND differing "${file}")
endforeach()
list(REMOVE_DUPLICATES differing)
list(LENGTH differing differing_count)
if(differing_count EQUAL 0)  # clang-format failed for another reason: show what it said
  message(FATAL_ERROR "format: ${CLANG_FORMAT} exited with ${status}:\n${err}")
endif()
list(JOIN differing "\n  " differing_text)
list(JOIN differing " " differing_args)
message(FATAL_ERROR "format: ${differing_count} of ${file_count} files differ from .clang-format:\n"
  "  ${differing_text}\n"
  "Fix with: clang-format -i ${differing_args}")
