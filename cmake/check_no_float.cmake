# Fail if an image links a floating-point helper or a libm function (the q family must not).
#   cmake -DNM=arm-none-eabi-nm -DELF=image.elf [-DEXPECT=fail] -P check_no_float.cmake
# Integer helpers (__aeabi_idiv, __aeabi_uldivmod, __aeabi_lmul, ...) are fine. With EXPECT=fail
# the check must find a float symbol (the canary image), so the check itself is tested.
execute_process(COMMAND ${NM} --defined-only ${ELF} OUTPUT_VARIABLE syms RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "check_no_float: ${NM} failed on ${ELF}")
endif()
# __aeabi_f*/__aeabi_d* (float and double arithmetic, compares, conversions), __aeabi_*2f/2d
# (integer to float), libgcc's __addsf3 ... __truncdfsf2, and libm.
set(re "(__aeabi_[fd][a-z0-9]*|__aeabi_[a-z0-9]+2[fd]|__[a-z]+[sdt]f[0-9]|__float[a-z]*|__fix[a-z]*[sd]f[a-z]*|(exp|expm1|log|log2|log10|pow|sqrt|sin|cos|tan|sinh|cosh|tanh|floor|ceil|fabs|round|lround|llround|ldexp|frexp|fmod|modf|fmax|fmin)f?)$")
set(found "")
string(REPLACE "\n" ";" lines "${syms}")
foreach(line IN LISTS lines)
  if(line MATCHES " [TtWw] ([A-Za-z0-9_]+)$")
    set(sym "${CMAKE_MATCH_1}")
    if(sym MATCHES "^${re}")
      list(APPEND found "${sym}")
    endif()
  endif()
endforeach()
get_filename_component(name ${ELF} NAME)
if(EXPECT STREQUAL "fail")
  if(found STREQUAL "")
    message(FATAL_ERROR "check_no_float: ${name} uses float, but the check found no float symbol")
  endif()
  message(STATUS "check_no_float: ${name} rejected as it must be (${found})")
elseif(NOT found STREQUAL "")
  message(FATAL_ERROR "check_no_float: ${name} links floating point: ${found}")
else()
  message(STATUS "check_no_float: ${name} links no floating-point helper and no libm function")
endif()
