// TetGen 1.5 compiled as one translation unit, with its assertions turned into the same
// exception TetGen throws for an internal error (int 2) instead of abort(): the process that
// calls TetGen must never die because one input was bad. The TetGen sources are in ../tetgen/
// (or $TETGEN_SRC_DIR); build.rs puts their directory on the include path.
//
// Everything tetgen.cxx includes is included first, so that no later #include <assert.h>
// can bring the standard assert back after we redefine it.
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <math.h>
#include <time.h>
#include <assert.h>
#include <stdint.h>
#include <vector>
#include <iomanip>
#include <iostream>
#include <sstream>
#include "tetgen.h"
#include "auxiliary.h"

// Text of the last failed assertion, read by shim.cpp after catching the exception.
char tetgen_shim_assert_text[512];

static void tetgen_shim_assert_failed(const char *expr, const char *file, int line) {
  snprintf(tetgen_shim_assert_text, sizeof tetgen_shim_assert_text,
           "assertion `%s` failed at %s:%d", expr, file, line);
  throw 2;
}

#undef assert
#define assert(e) ((e) ? (void)0 : tetgen_shim_assert_failed(#e, __FILE__, __LINE__))

#include "tetgen.cxx"
