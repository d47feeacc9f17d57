/* io_ply.c: to be written. */
#include "internal.h"
