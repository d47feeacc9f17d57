/* io_stl.c: to be written. */
#include "internal.h"
