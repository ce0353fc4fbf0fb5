# Builds one libFuzzer binary from a fuzz target (cmake -P): the harness (fuzz_<t>.c +
# fuzz_entry.c) compiled by clang with -fsanitize=fuzzer-no-link and linked with
# -fsanitize=fuzzer against the same libraries as the target's replay driver (read from its
# link.txt, Makefile generators), so the gcc-built libvbl needs no second build. Only the
# harness is instrumented: libFuzzer then explores by the inputs' effect on the entry points.
# Arguments: CLANG, CLANGXX, SOURCES (;-list), INCLUDES (;-list), LINK_TXT, OUTPUT.
file(READ ${LINK_TXT} link)
string(STRIP "${link}" link)
# "<compiler> <flags> <objects> -o <name> <libraries...>": keep what follows the output name
string(REGEX REPLACE "^.* -o [^ ]+ " "" libraries "${link}")
separate_arguments(libraries UNIX_COMMAND "${libraries}")
get_filename_component(build_dir ${LINK_TXT} DIRECTORY)
get_filename_component(build_dir ${build_dir}/../.. ABSOLUTE) # link.txt paths are relative to here
set(objects)
foreach(include ${INCLUDES})
  list(APPEND include_flags -I${include})
endforeach()
foreach(source ${SOURCES})
  get_filename_component(stem ${source} NAME_WE)
  set(object ${OUTPUT}.${stem}.o)
  execute_process(COMMAND ${CLANG} -O1 -g -fsanitize=fuzzer-no-link ${include_flags} -c ${source} -o ${object}
                  RESULT_VARIABLE rc)
  if(NOT rc EQUAL 0)
    message(FATAL_ERROR "clang could not compile ${source}")
  endif()
  list(APPEND objects ${object})
endforeach()
execute_process(COMMAND ${CLANGXX} -fsanitize=fuzzer ${objects} -o ${OUTPUT} ${libraries}
                WORKING_DIRECTORY ${build_dir} RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "clang++ could not link ${OUTPUT}")
endif()
