/* Turn a non-zero exit of the fuzz harness into SIGABRT, which the fuzzer counts as a crash.
 *
 * A failed gfortran runtime check (-fcheck=all: an index out of bounds, an unallocated array,
 * a failed allocation) prints its message and calls exit(2); AFL++ only sees signals. The
 * harness itself always ends with status 0 (an input error is a normal answer), so any other
 * status comes from a runtime check, an ERROR STOP or a STOP in library code, all of them bugs.
 * Defining exit() in the executable interposes it for libgfortran.so as well; the real exit()
 * is found with RTLD_NEXT. */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdlib.h>
#include <unistd.h>

void exit(int status)
{
    if (status != 0) {
        abort();
    }
    void (*real_exit)(int) = (void (*)(int))dlsym(RTLD_NEXT, "exit");
    if (real_exit != NULL) {
        real_exit(0);
    }
    _exit(0);
}
