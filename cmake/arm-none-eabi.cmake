# Cross toolchain: GNU Arm Embedded (arm-none-eabi-gcc 12, newlib), bare metal.
#
# Selected by the CMake presets cortex-m4f and cortex-m7 together with the
# cache variable AOCS_ARM_CPU:
#   cortex-m4f  -mcpu=cortex-m4 -mfpu=fpv4-sp-d16 (single-precision FPU;
#               the preset builds real_t = float)
#   cortex-m7   -mcpu=cortex-m7 -mfpu=fpv5-d16 (double-precision FPU;
#               the preset builds real_t = double)
# both -mthumb -mfloat-abi=hard.
#
# Optimisation comes from CMAKE_BUILD_TYPE (the ARM presets use RelWithDebInfo,
# i.e. -O2 -g: what a flight build would run, so the size and stack reports
# describe the code that flies; -g does not change text/data/bss).
#
# Every object also gets -ffunction-sections -fdata-sections (the link uses
# --gc-sections) and -fstack-usage -fcallgraph-info=su, which write
# <obj-dir>/<file>.c.su and <file>.c.ci next to each object for
# scripts/size-report.sh (worst-case stack per law step).
#
# Enums: -fno-short-enums. arm-none-eabi defaults to the AAPCS "variable
# size" enums (an enum of small values is one byte); the firmware is written
# and tested on the host, where enums are int-sized. Keeping them int-sized on
# the target gives the same struct layouts on both (executive output,
# anything sent over PIL/telemetry) and keeps the firmware's range checks of
# enum values (e.g. (int)status >= 0 in status.c) meaningful instead of
# "always true" (-Wtype-limits, an error under -Werror). newlib/libgcc are
# built with variable-size enums but no enum crosses their interface (libm
# takes and returns floats), so the linker's enum-size note is switched off
# with --no-enum-size-warning.
#
# Libraries: newlib-nano (--specs=nano.specs) and nosys stubs
# (--specs=nosys.specs). The image does its own startup
# (port/cortex-m/startup.S) and talks to the host through raw semihosting
# calls, so no stdio and therefore no malloc is linked (checked by
# scripts/check-no-malloc.sh).

set(CMAKE_SYSTEM_NAME Generic)
set(CMAKE_SYSTEM_PROCESSOR arm)

set(AOCS_ARM_CPU "cortex-m4f" CACHE STRING "Target core: cortex-m4f or cortex-m7")
set_property(CACHE AOCS_ARM_CPU PROPERTY STRINGS cortex-m4f cortex-m7)
# try_compile() re-reads this file in a scratch project: forward the choice.
list(APPEND CMAKE_TRY_COMPILE_PLATFORM_VARIABLES AOCS_ARM_CPU)

set(CMAKE_C_COMPILER arm-none-eabi-gcc)
set(CMAKE_ASM_COMPILER arm-none-eabi-gcc)
set(CMAKE_AR arm-none-eabi-ar CACHE FILEPATH "")
set(CMAKE_RANLIB arm-none-eabi-ranlib CACHE FILEPATH "")
set(CMAKE_OBJCOPY arm-none-eabi-objcopy CACHE FILEPATH "")
set(CMAKE_SIZE arm-none-eabi-size CACHE FILEPATH "")
set(CMAKE_NM arm-none-eabi-nm CACHE FILEPATH "")

# No executable can be linked without our linker script and startup.
set(CMAKE_TRY_COMPILE_TARGET_TYPE STATIC_LIBRARY)

if(AOCS_ARM_CPU STREQUAL "cortex-m4f")
  set(_aocs_cpu_flags "-mcpu=cortex-m4 -mthumb -mfpu=fpv4-sp-d16 -mfloat-abi=hard")
elseif(AOCS_ARM_CPU STREQUAL "cortex-m7")
  set(_aocs_cpu_flags "-mcpu=cortex-m7 -mthumb -mfpu=fpv5-d16 -mfloat-abi=hard")
else()
  message(FATAL_ERROR "AOCS_ARM_CPU must be cortex-m4f or cortex-m7, got '${AOCS_ARM_CPU}'")
endif()

set(CMAKE_C_FLAGS_INIT
  "${_aocs_cpu_flags} -fno-short-enums -ffunction-sections -fdata-sections -fstack-usage -fcallgraph-info=su")
set(CMAKE_ASM_FLAGS_INIT "${_aocs_cpu_flags} -x assembler-with-cpp")
set(CMAKE_EXE_LINKER_FLAGS_INIT
  "${_aocs_cpu_flags} --specs=nano.specs --specs=nosys.specs -nostartfiles -Wl,--gc-sections -Wl,--no-enum-size-warning -Wl,--print-memory-usage")

# Find headers and libraries only in the cross sysroot, programs on the host.
set(CMAKE_FIND_ROOT_PATH_MODE_PROGRAM NEVER)
set(CMAKE_FIND_ROOT_PATH_MODE_LIBRARY ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_INCLUDE ONLY)
set(CMAKE_FIND_ROOT_PATH_MODE_PACKAGE ONLY)
