/* valgrind-hwy-timer.c: a preload shim that lets valgrind run our processes on hosts whose
 * CPUID hides RDTSCP (docs/testing.md, "Valgrind on hosts without RDTSCP").
 *
 * OpenImageIO links ffmpeg, which links libjxl, which links Highway (libhwy). libhwy's
 * static initializer calls hwy::platform::TimerResolution(), which executes RDTSCP
 * without asking CPUID first. Natively that works on every x86-64 CPU we meet, even
 * inside VMs that clear the CPUID bit. Valgrind 3.19 decodes RDTSCP only when the
 * host's CPUID reports it, so on such VMs every process dies with SIGILL before main.
 *
 * The initializer reaches TimerResolution through the PLT, so this library, preloaded
 * by scripts/valgrind-suite, interposes it. The value only seeds Highway's own
 * benchmark timer, which nothing in planetgen calls; 1 tick is a valid resolution.
 * C has no C++ names, so the symbol is given by its Itanium mangling. */
#include <stdint.h>

uint64_t vg_hwy_timer_resolution(void) __asm__("_ZN3hwy8platform15TimerResolutionEv");

uint64_t vg_hwy_timer_resolution(void) {
    return 1;
}
