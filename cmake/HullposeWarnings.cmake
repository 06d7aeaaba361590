# The project's warning set. hullpose_target_warnings(<target>) applies it; with
# HULLPOSE_WERROR (default ON) every one of them is an error.
set(HULLPOSE_WARNINGS
  -Wall -Wextra -Wpedantic
  -Wshadow
  -Wnon-virtual-dtor
  -Wold-style-cast
  -Wcast-align
  -Wunused
  -Woverloaded-virtual
  -Wnull-dereference
  -Wdouble-promotion
  -Wformat=2
  -Wimplicit-fallthrough
  -Wmisleading-indentation
)

function(hullpose_target_warnings target)
  set(flags ${HULLPOSE_WARNINGS})
  if(HULLPOSE_WERROR)
    list(APPEND flags -Werror)
  endif()
  target_compile_options(${target} PRIVATE $<$<COMPILE_LANGUAGE:CXX>:${flags}>)
endfunction()

if(HULLPOSE_NATIVE AND NOT HULLPOSE_FUZZ)
  add_compile_options($<$<COMPILE_LANGUAGE:CXX>:-march=native>)
endif()
